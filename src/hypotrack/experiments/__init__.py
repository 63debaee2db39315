"""Experiment drivers: run the library's trackers over the papers' scenarios and summarise them.

Each driver turns saved scenario tables into per-scan tables (posterior summaries, metrics,
snapshots), figures and reproduction claims; the pipeline's scripts only read and write files.

Modules
-------
ssa_tracking   seed 000 Sec. IV–V: R-FISST on the 50-object birth scenario (Figs 6, 8–11) and
               R-FISST vs HOMHT on the 15-object scenario (Figs 12–14).
"""
