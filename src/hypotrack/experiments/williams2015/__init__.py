"""The Williams-2015 scenario of the PMBM paper: every registered tracker on the same scans (rule ``williams2015``).

Modules
-------
scenario   the truth (trajectories meeting at the mid-point), the returns, the tracking problem
run        Monte Carlo shards: GOSPA per scan, trajectory GOSPA per run, time per scan
summary    the side-by-side table, curves over time, figure, ledger rows and macros
reference  the PMBM paper's own code under GNU Octave on this project's exported scans
record     the committed record of that run (``paper/record/williams2015_reference*``)
compare    the reference beside this project's trackers on the same runs
kbest      Murty's k best: murty_k_best against nrl-tracker's on the same costs
"""
