"""Document 003's published numbers for the closely spaced targets (Table 6.1)."""

__all__ = ["TABLE_6_1"]

#: Published MOSPA (m², see reconstruction §5.4) of Table 6.1 (1,000 runs).
TABLE_6_1 = {"ideal": 0.0363, "PDAF": 0.8518, "MHT": 0.1376, "ECMHT": 0.0586}
