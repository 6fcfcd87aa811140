"""The rotor model.

==========  ===================================================================
module      what it holds
==========  ===================================================================
band_modes  a big rotor's damped modes about a frequency band, sparse (ARPACK
            shift-invert), without an n x n matrix
fe          Timoshenko beam and rigid disk element matrices
rotor       the rotor file's keys, ``Rotor`` (assembly of M, K, G, C; weight,
            unbalance, loads; modes)
speed       ``SpeedProfile``: constant speed or a run-up / coast-down
==========  ===================================================================
"""
