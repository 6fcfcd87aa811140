"""The bore: its shape, the solver's grid of it, the tilting pads' frame, the feed's place.

=================  ============================================================
module             what it holds
=================  ============================================================
geometry           ``Geometry``: the bore (grooves, partial arc, lobes with preload, a
                   circumferential groove), the [geometry] keys, the lobed film
thetagrid          ``ThetaGrid``: the solver's circumferential grid of a bore that is not
                   the full circle (cells, fixed-pressure cells, the film's edges)
pads               the tilting pads' keys, checks and the pad frame (the film derived)
feed               a feed at the line of thickest film, placed with the load
=================  ============================================================
"""
