"""Per-scan timing of GNN and JPDA against Stone Soup (rule ``perf_sht``).

Modules
-------
run  the side-by-side benchmark, its tables and timing rows
"""
