"""The compiled kernels' base: C-contiguous arrays, numba's cache keyed by code, the build notice
and the warm-up registry."""
