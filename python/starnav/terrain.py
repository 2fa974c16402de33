"""Terrain: analysis layers of an elevation map (ruggedness, slope, normals, the Liu 2024 obstacle
mask, Li 2019's node criteria) and the seeded terrain generators (docs/terrain.md). The keyword
arguments are the library's declared parameters of each (help(starnav.terrain.hills))."""
from . import _starnav
from ._generate import table_function
from ._starnav import TerrainAnalysis, with_feature

analyse = table_function(
    "analyse", "starnav.terrain", "terrain_analysis", lambda map, **params: _starnav.analyse_terrain(map, **params),
    ["map"], "The terrain analysis of an ElevationMap: a starnav.TerrainAnalysis.")
hills = table_function(
    "hills", "starnav.terrain", "hills", lambda **params: _starnav.generate_hills(**params), [],
    "A seeded terrain of Gaussian hills plus small-scale roughness (the Liu 2024 experiment's): an ElevationMap.\n"
    "The same seed and options give the same heights, bit for bit.")
road = table_function(
    "road", "starnav.terrain", "road", lambda **params: _starnav.generate_road(**params), [],
    "Seeded stochastic ground of a road-roughness class (ISO 8608 / GB/T 7031, Li 2019): an ElevationMap.")

__all__ = ["TerrainAnalysis", "analyse", "hills", "road", "with_feature"]
