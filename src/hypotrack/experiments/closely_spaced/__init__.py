"""Document 003 Table 6.1 and Figs 6.1–6.2: two closely spaced OU targets, N sensors (rule ``closely_spaced``).

Modules
-------
run      Monte Carlo shards of the ideal filter, GNN, PDAF and ECMHT
oracle   the ideal filter's MOSPA in closed form (Riccati moments), every convention
figures  MOSPA over time and Figs 6.1–6.2
claims   Table 6.1 ledger rows: Monte Carlo verdicts, closed form, published ideal
controls the filters with a known defect (negative controls), the broken MHTs among them
power    every broken MHT through the MHT row's check, and its paired difference from the MHT
"""
