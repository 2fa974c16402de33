#!/usr/bin/env python3
"""Writes ren_room_empty.{pgm,yaml} and ren_room_obstacles.{pgm,yaml} (map_server, trinary, 0.05 m):
the 20 m x 20 m room of Ren et al. 2022's Table 1 (A* against Dijkstra from (1, 1) m to (18, 18) m),
walled, empty or with a fixed set of obstacles between the two corners (cabinets, a partition
with a gap, equipment blocks), so that the straight line is blocked and the search must go round.
Deterministic: run it again and the bytes are the same."""
import os

from occupancy_paint import Floor

RES = 0.05
W = H = 20.0
HERE = os.path.dirname(os.path.abspath(__file__))


def room():
    floor = Floor(W, H, RES)
    t = 0.1
    for box in ((0, 0, W, t), (0, H - t, W, H), (0, 0, t, H), (W - t, 0, W, H)):
        floor.paint(*box, True)
    return floor


room().write(HERE, "ren_room_empty")

floor = room()
obstacles = [
    (4.0, 2.5, 4.6, 9.0),      # a row of cabinets across the diagonal
    (2.5, 12.0, 11.0, 12.4),   # a partition, open at its east end
    (8.0, 4.0, 12.0, 7.0),     # an equipment block
    (14.0, 9.0, 14.4, 17.5),   # a second partition, open at its south end
    (11.5, 14.5, 13.0, 16.0),  # a cabinet
    (16.0, 3.0, 18.5, 4.0),    # a desk
    (6.0, 15.0, 7.0, 18.0),    # shelves
]
for box in obstacles:
    floor.paint(*box, True)
floor.write(HERE, "ren_room_obstacles")
