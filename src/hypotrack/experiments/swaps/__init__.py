"""Seed 003 §5: the track-swap experiment, Figs 5.1–5.3 (rule ``swaps``).

Modules
-------
run      GNNF vs MHT vs ECMHT on the static pair; swap rates over Monte Carlo runs
figures  Figs 5.1–5.3
claims   the ledger rows of Figs 5.1–5.3, each with its negative control
"""
