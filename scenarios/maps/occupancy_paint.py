"""Shared by the map generators here: a grid of occupied flags painted by rectangles in metres,
written as a map_server trinary map (PGM + YAML, origin at the lower-left corner)."""
import os


class Floor:
    def __init__(self, width_m, height_m, resolution):
        self.res = resolution
        self.nx, self.ny = round(width_m / resolution), round(height_m / resolution)
        self.occ = [[False] * self.nx for _ in range(self.ny)]

    def paint(self, x0, y0, x1, y1, value):
        """Sets the cells whose centres lie in [x0, x1] x [y0, y1] (metres)."""
        for iy in range(self.ny):
            cy = (iy + 0.5) * self.res
            if cy < y0 or cy > y1:
                continue
            for ix in range(self.nx):
                cx = (ix + 0.5) * self.res
                if x0 <= cx <= x1:
                    self.occ[iy][ix] = value

    def write(self, folder, stem):
        with open(os.path.join(folder, stem + ".pgm"), "wb") as f:
            f.write(b"P5\n%d %d\n255\n" % (self.nx, self.ny))
            for iy in reversed(range(self.ny)):  # image row 0 is the map's top
                f.write(bytes(0 if self.occ[iy][ix] else 254 for ix in range(self.nx)))
        with open(os.path.join(folder, stem + ".yaml"), "w") as f:
            f.write("image: %s.pgm\nresolution: %s\norigin: [0.0, 0.0, 0.0]\nnegate: 0\n"
                    "occupied_thresh: 0.65\nfree_thresh: 0.196\nmode: trinary\n" % (stem, self.res))
