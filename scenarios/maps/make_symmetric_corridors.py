#!/usr/bin/env python3
"""Writes symmetric_corridors.pgm and symmetric_corridors.yaml (map_server, trinary, 0.05 m): a
24 m x 12 m floor with two corridors 3 m wide, south and north of a closed central block, joined
by a hall at each end. Everything but one crate is point-symmetric about the centre (12, 6): a
pose in the south corridor and the pose turned half round in the north corridor see the same
scan, so a localizer must not claim either until the robot has looked through the door of the
east store room (in the block's east face, seen only from the east hall) at a crate that the west
store room lacks. The map of scenarios/amcl_symmetric_corridors.yaml. Deterministic: run it again
and the bytes are the same."""
import os

from occupancy_paint import Floor

RES = 0.05
W, H = 24.0, 12.0
floor = Floor(W, H, RES)
paint = floor.paint


def box_pair(x0, y0, x1, y1):
    """A box and its image under the half turn about the centre."""
    paint(x0, y0, x1, y1, True)
    paint(W - x1, H - y1, W - x0, H - y0, True)


t = 0.1  # wall thickness
# Outer walls (the outline is its own image).
box_pair(0, 0, W, t)
box_pair(0, 0, t, H)
# The central block between the corridors, x 3.5-20.5, y 4.5-7.5.
paint(3.5, 4.5, 20.5, 7.5, True)
# Cabinets 0.6 m x 0.4 m on the outer south wall, unevenly spaced, and their images on the north wall.
for x in (4.2, 7.9, 12.6, 17.1):
    box_pair(x, t, x + 0.6, t + 0.4)
# Pillars 0.4 m x 0.4 m along the central block's south face and their images on its north face.
for x in (6.0, 10.5, 15.3):
    box_pair(x, 4.1, x + 0.4, 4.5)
# Benches in the halls: one in the west hall, its image in the east hall.
box_pair(0.9, 2.0, 1.5, 3.2)
# A store room at each end of the central block, its door in the block's end face (seen only
# from the hall in front of it, never from a corridor).
paint(17.6, 4.6, 20.4, 7.4, False)
paint(3.6, 4.6, 6.4, 7.4, False)
paint(20.4, 5.5, 20.5, 6.5, False)
paint(3.5, 5.5, 3.6, 6.5, False)
# The one asymmetric feature: a crate in the east store room; the west one is empty.
paint(18.2, 4.9, 19.0, 5.5, True)

floor.write(os.path.dirname(os.path.abspath(__file__)), "symmetric_corridors")
