"""Map geometry: polygon worlds (:mod:`ecoplan.geometry.world`) and occupancy/terrain grids.

See :mod:`ecoplan.geometry.world` for polygon maps and :mod:`ecoplan.geometry.maps` for
grid maps (ROS ``map_server`` occupancy grids with terrain layers).
"""
