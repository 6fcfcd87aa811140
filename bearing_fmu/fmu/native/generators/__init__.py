"""The native FMU's model of each internal, one module each (as the FMI Reference FMUs keep one
folder per model): its generator (data and start values as a ``codegen.NativeModel``, its
model_data.h) beside its C files in ``c/``. The catalogue (``..catalogue.NATIVE``) names them.

| module | internal | data compiled in |
|---|---|---|
| linear | linear | none: the coefficients are parameters |
| map | map | the force map's spline, its flow table's |
| reynolds | reynolds | the bore's segments, the wall's sample angles |
| taylor | taylor | the surrogate's polynomials, training states, film fit |
"""
