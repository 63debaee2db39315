"""What input validation costs (rule ``perf_validation``).

Modules
-------
run  checked vs unchecked Gaussian kernels; the share of a tracker's step spent in checks
"""
