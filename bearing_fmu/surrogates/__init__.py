"""The Taylor surrogate as data: its file, its monomial basis, its compiled kernels (the
internal that evaluates it is ``bearing_fmu.internals.taylor``; fitting it is
``bearing_fmu.fitting``).

================  =============================================================
module            what it holds
================  =============================================================
surrogate         the surrogate file: schema, load, save (re-exports Domain, Neighbours)
domain            its fitted domain and training states; the checked readers of its values
basis             the monomial basis (exponents, names, shape columns)
taylor_kernels    the compiled kernels: force, Jacobian, domain distance
================  =============================================================
"""
