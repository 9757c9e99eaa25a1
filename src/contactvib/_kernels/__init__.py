"""Compiled kernels (numba, ``cache=True``): arrays and scalars in, arrays and status codes out.

They know nothing of units, files or plots; the public modules validate, call and interpret.
"""
