"""The map internal: the Reynolds force reduced exactly to a table (docs/forcemap.md).

==========  ====================================================================
module      what it holds
==========  ====================================================================
tables      the full bore's reduction (eccentricity and one angle), ``MapTable``
            (axes, spline, the file's content) and its tabulation from Reynolds
tablefile   the full bore's map file: ``save_map``, ``load_map`` (every key checked)
forcemap    ``ForceMap``: the internal evaluating a full-bore table
groovemap   the grooved or partial-arc bore's 3-D map: table, file and internal
supplymap   grooves fed at a supply pressure: the 4-D map (u = p_s / (p_s + k r)),
            exact by the joint homogeneity in (r, p_s); supplykernels its spline
lobemap     a lobed bore with ambient grooves over its lobe boundaries: the sum of
            its lobes' partial-arc maps (one 3-D map of the lobe's arc), exact
mapfile     either map file (``load_any_map``) and the map internal's factory
kernels     the compiled splines: force, Jacobian, flows, the lobe sum (numba)
store       the map store: maps keyed by a hash of what determines them
build       ``bearing-fmu map``: rows as tasks (process pool or Dask), resumed
            from the partial file, the map written into the store
==========  ====================================================================
"""
