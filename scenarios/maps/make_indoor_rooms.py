#!/usr/bin/env python3
"""Writes indoor_rooms.pgm and indoor_rooms.yaml (map_server, trinary, 0.05 m): a 24 m x 16 m floor
with a ring corridor 3.4 m wide around three rooms, doors into them, and cabinets along the walls
(so that no stretch of the corridor is featureless). The world of scenarios/indoor_slam.yaml.
Deterministic: run it again and the bytes are the same."""
import os

from occupancy_paint import Floor

RES = 0.05
W, H = 24.0, 16.0
floor = Floor(W, H, RES)
paint = floor.paint


def box(x0, y0, x1, y1):
    paint(x0, y0, x1, y1, True)


def clear(x0, y0, x1, y1):
    paint(x0, y0, x1, y1, False)


t = 0.1  # wall thickness
# Outer walls.
box(0, 0, W, t); box(0, H - t, W, H); box(0, 0, t, H); box(W - t, 0, W, H)
# The central block of three rooms, its walls with doors.
box(3.5, 3.5, 20.5, 3.5 + t); box(3.5, 12.5 - t, 20.5, 12.5); box(3.5, 3.5, 3.5 + t, 12.5); box(20.5 - t, 3.5, 20.5, 12.5)
box(9.5, 3.5, 9.5 + t, 12.5); box(14.5, 3.5, 14.5 + t, 12.5)
for x in (6.0, 12.0, 17.5):
    clear(x, 3.4, x + 1.0, 3.7)      # doors from the south corridor
for x in (5.0, 16.0):
    clear(x, 12.3, x + 1.0, 12.6)    # doors from the north corridor
clear(9.4, 7.0, 9.7, 8.0)            # between the rooms
clear(14.4, 9.0, 14.7, 10.0)
# Cabinets 0.6 m x 0.4 m against the outer walls, unevenly spaced.
for x in (2.3, 5.1, 8.9, 10.4, 13.7, 17.2, 19.9, 22.6):
    box(x, t, x + 0.6, t + 0.4)
for x in (1.6, 4.4, 7.8, 11.9, 12.8, 16.6, 21.3):
    box(x, H - t - 0.4, x + 0.6, H - t)
for y in (2.2, 5.6, 9.1, 13.2):
    box(t, y, t + 0.4, y + 0.6)
for y in (1.8, 4.9, 8.3, 11.6, 14.0):
    box(W - t - 0.4, y, W - t, y + 0.6)
# Equipment inside the rooms.
box(5.0, 6.0, 6.2, 6.8); box(7.4, 9.6, 8.0, 11.0); box(11.0, 5.0, 11.6, 5.6); box(12.6, 10.2, 13.8, 11.0)
box(16.2, 6.4, 17.0, 7.2); box(18.4, 8.8, 19.4, 9.4)

floor.write(os.path.dirname(os.path.abspath(__file__)), "indoor_rooms")
