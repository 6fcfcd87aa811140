"""The rotor model.

=======  ======================================================================
module   what it holds
=======  ======================================================================
fe       Timoshenko beam and rigid disk element matrices
rotor    the rotor file's keys, ``Rotor`` (assembly of M, K, G, C; weight,
         unbalance, loads; modes)
speed    ``SpeedProfile``: constant speed or a run-up / coast-down
=======  ======================================================================
"""
