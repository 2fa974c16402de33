#!/usr/bin/env python3
"""Writes the hand-made seed inputs of every fuzz target into fuzz/corpus/<target>/.

All of these are written here from scratch (nothing is copied from ../shared/), except that
fuzz_scenario also gets the repository's own scenarios/*.yaml without their comments, and the ROS 2
targets two of rosbag2's own test bags from tests/data/rosbag2. They are small
valid files of each format plus a few interesting invalid ones. scripts/fuzz.sh runs this only when
a target's corpus folder is empty; the committed corpus is what `-merge=1` kept afterwards.
Usage: fuzz/seeds/make_seeds.py [CORPUS_DIR]   (default: fuzz/corpus beside this script)
"""
import os
import struct
import sys
import zlib

SEP = b"\n#@@\n"  # fuzz_drivers.hpp kFileSeparator


def png(width, height, color_type, bit_depth, rows, palette=None, trns=None, interlace=0, extra=b""):
    """A PNG from raw scanlines (each row given without its filter byte; filter 0 is added)."""
    def chunk(kind, data):
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF)

    ihdr = struct.pack(">IIBBBBB", width, height, bit_depth, color_type, 0, 0, interlace)
    out = b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", ihdr)
    if palette is not None:
        out += chunk(b"PLTE", palette)
    if trns is not None:
        out += chunk(b"tRNS", trns)
    out += extra
    raw = b"".join(b"\x00" + r for r in rows)
    out += chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b"")
    return out


def grey8(w, h):
    return [bytes((x * 37 + y * 91) & 0xFF for x in range(w)) for y in range(h)]


def grey16(w, h):
    return [b"".join(struct.pack(">H", (x * 4099 + y * 12345) & 0xFFFF) for x in range(w)) for y in range(h)]


def pngs():
    w, h = 5, 4
    return {
        "grey8.png": png(w, h, 0, 8, grey8(w, h)),
        "grey16.png": png(w, h, 0, 16, grey16(w, h)),
        "grey1.png": png(9, 3, 0, 1, [b"\xa5\x80"] * 3),
        "grey4.png": png(4, 2, 0, 4, [b"\x0f\xa5", b"\x12\x34"]),
        "greyalpha8.png": png(3, 2, 4, 8, [bytes([0, 255, 128, 0, 254, 200])] * 2),
        "greyalpha16.png": png(2, 2, 4, 16, [b"\xff\xff\x00\x00\x12\x34\xff\xff"] * 2),
        "rgb8.png": png(3, 2, 2, 8, [bytes([0, 0, 0, 255, 255, 255, 10, 200, 30])] * 2),
        "rgb16.png": png(2, 1, 2, 16, [b"\x00\x01\x00\x02\x00\x03\xff\xff\x80\x00\x00\x00"]),
        "rgba8.png": png(2, 2, 6, 8, [bytes([1, 2, 3, 255, 250, 250, 250, 0])] * 2),
        "palette.png": png(4, 2, 3, 8, [bytes([0, 1, 2, 1])] * 2, palette=bytes([0, 0, 0, 205, 205, 205, 254, 254, 254])),
        "palette_trns.png": png(4, 1, 3, 2, [b"\x1b"], palette=bytes([0, 0, 0, 255, 0, 0, 0, 255, 0]), trns=b"\x00\x80"),
        "grey_trns.png": png(2, 2, 0, 8, [b"\x05\xfe"] * 2, trns=b"\x00\xfe"),
        "interlaced.png": png(1, 1, 0, 8, [b"\x7f"], interlace=1),
        "truncated.png": png(5, 4, 0, 8, grey8(5, 4))[:40],
        "bad_crc.png": png(2, 2, 0, 8, [b"\x00\x01"] * 2)[:-1] + b"\x00",
        "huge_ihdr.png": png(2, 2, 0, 8, [b"\x00\x01"] * 2).replace(
            struct.pack(">II", 2, 2), struct.pack(">II", 1000000, 1000000), 1),
        "empty.png": b"",
        "magic_only.png": b"\x89PNG\r\n\x1a\n",
        # Valid CRCs, header of a 40000 x 40000 RGBA16 image (12.8 GB decoded), no pixel data.
        "big_header_no_data.png": png(40000, 40000, 6, 16, [b""]),
    }


def pgms():
    body8 = bytes(range(0, 240, 20))  # 4 x 3
    body16 = b"".join(struct.pack(">H", v) for v in (0, 1, 1000, 65535, 32768, 7))
    return {
        "p5_8bit.pgm": b"P5\n4 3\n255\n" + body8,
        "p5_comment.pgm": b"P5\n# CREATOR: hand-written seed\n4 3\n255\n" + body8,
        "p5_16bit.pgm": b"P5 3 2 65535\n" + body16,
        "p5_maxval100.pgm": b"P5\n2 2\n100\n" + bytes([0, 50, 99, 100]),
        "p2_8bit.pgm": b"P2\n# ascii\n3 2\n255\n0 128 255\n205 254 1\n",
        "p2_16bit.pgm": b"P2\n2 2\n65535\n0 65535\n300 12\n",
        "p2_comments_everywhere.pgm": b"P2 # a\n2 # b\n1 # c\n15 # d\n3 # e\n15\n",
        "truncated.pgm": b"P5\n4 3\n255\n\x00\x01",
        "huge.pgm": b"P5\n100000 100000\n255\n\x00",
        "maxval0.pgm": b"P5\n1 1\n0\n\x00",
        "maxval_big.pgm": b"P5\n1 1\n70000\n\x00\x00",
        "negative.pgm": b"P2\n-3 2\n255\n0 0 0\n",
        "p6.pgm": b"P6\n1 1\n255\n\x00\x00\x00",
        "empty.pgm": b"",
    }


def maps():
    lf = b"type octile\nheight 3\nwidth 4\nmap\n.@.T\nGS.O\nW...\n"
    return {
        "small.map": lf,
        "crlf.map": lf.replace(b"\n", b"\r\n"),
        "crlf_no_final_newline.map": lf.replace(b"\n", b"\r\n")[:-2],
        "no_final_newline.map": lf[:-1],
        "one_cell.map": b"type octile\nheight 1\nwidth 1\nmap\n.\n",
        "width_first.map": b"type octile\nwidth 2\nheight 2\nmap\n..\n@@\n",
        "short_row.map": b"type octile\nheight 2\nwidth 3\nmap\n...\n..\n",
        "long_row.map": b"type octile\nheight 1\nwidth 2\nmap\n...\n",
        "missing_row.map": b"type octile\nheight 3\nwidth 2\nmap\n..\n..\n",
        "extra_row.map": b"type octile\nheight 1\nwidth 2\nmap\n..\n..\n",
        "bad_char.map": b"type octile\nheight 1\nwidth 3\nmap\n.x.\n",
        "zero.map": b"type octile\nheight 0\nwidth 0\nmap\n",
        "negative.map": b"type octile\nheight -1\nwidth 2\nmap\n..\n",
        "huge.map": b"type octile\nheight 2147483647\nwidth 2147483647\nmap\n.\n",
        "overflow.map": b"type octile\nheight 99999999999999999999\nwidth 1\nmap\n.\n",
        "no_type.map": b"height 1\nwidth 1\nmap\n.\n",
        "empty.map": b"",
    }


def scens():
    v1 = (b"version 1\n"
          b"0\tmaps/dao/tiny.map\t4\t3\t0\t0\t3\t2\t3.82842712\n"
          b"1\ttiny.map\t4\t3\t2\t1\t2\t1\t0\n"
          b"3\ttiny.map\t4\t3\t0\t2\t3\t0\t0\n")
    return {
        "v1.scen": v1,
        "v1_crlf.scen": v1.replace(b"\n", b"\r\n"),
        "v1_no_final_newline.scen": v1[:-1],
        "v1_header_only.scen": b"version 1\n",
        "bg512.scen": b"version 1.0\n61 maps/bgmaps/tiny.map 4 3 0 0 3 2 3.83\n7 maps/bgmaps/tiny.map 4 3 1 1 2 1 1.00\n",
        "v1_exponent.scen": b"version 1\n0\tm.map\t4\t3\t0\t0\t1\t1\t1.4142e0\n",
        "v1_nan.scen": b"version 1\n0\tm.map\t4\t3\t0\t0\t1\t1\tnan\n",
        "v1_missing_field.scen": b"version 1\n0\tm.map\t4\t3\t0\t0\t1\t1\n",
        "v1_extra_field.scen": b"version 1\n0\tm.map\t4\t3\t0\t0\t1\t1\t1.41421\t9\n",
        "v1_negative.scen": b"version 1\n0\tm.map\t4\t3\t-1\t0\t1\t1\t1.4\n",
        "v1_overflow.scen": b"version 1\n0\tm.map\t4\t3\t99999999999\t0\t1\t1\t1.4\n",
        "version2.scen": b"version 2\n",
        "no_version.scen": b"0\tm.map\t4\t3\t0\t0\t1\t1\t1.4\n",
        "empty.scen": b"",
    }


def alias_bomb(levels=9):
    """Nine nested levels of ten aliases: 10^9 nodes once expanded, in a few hundred bytes."""
    out = b"l0: &l0 [x, x, x, x, x, x, x, x, x, x]\n"
    for i in range(1, levels):
        out += f"l{i}: &l{i} [".encode() + b", ".join([f"*l{i - 1}".encode()] * 10) + b"]\n"
    return out


def ros_yamls():
    image = b"P5\n3 2\n255\n\x00\xcd\xfe\x80\xff\x10"
    base = (b"image: m.pgm\nresolution: 0.05\norigin: [-10.0, -10.0, 0.0]\nnegate: 0\n"
            b"occupied_thresh: 0.65\nfree_thresh: 0.196\n")
    return {
        "map_saver.yaml": base,
        "map_saver_with_image.yaml": base + SEP + image,
        "trinary.yaml": base + b"mode: trinary\n" + SEP + image,
        "scale.yaml": base.replace(b"negate: 0", b"negate: 1") + b"mode: scale\n" + SEP + image,
        "raw.yaml": base + b"mode: raw\n" + SEP + image,
        "yaw.yaml": b"image: m.pgm\nresolution: 0.1\norigin: [2.0, 3.0, 1.0]\nnegate: false\noccupied_thresh: 0.65\nfree_thresh: 0.196\n",
        "flow.yaml": b"{image: m.pgm, resolution: 1, origin: [0, 0, 0], negate: 0, occupied_thresh: 0.9, free_thresh: 0.1}\n" + SEP + image,
        "extra_key.yaml": base + b"map_type: occupancy\n",
        "missing_resolution.yaml": b"image: m.pgm\norigin: [0, 0, 0]\nnegate: 0\noccupied_thresh: 0.65\nfree_thresh: 0.196\n",
        "bad_origin.yaml": base.replace(b"[-10.0, -10.0, 0.0]", b"[1, 2]"),
        "bad_mode.yaml": base + b"mode: fancy\n",
        "neg_resolution.yaml": base.replace(b"0.05", b"-0.05"),
        "nan_resolution.yaml": base.replace(b"0.05", b".nan"),
        "thresh_swapped.yaml": base.replace(b"0.65", b"0.1").replace(b"0.196", b"0.9"),
        "not_a_map.yaml": b"- 1\n- 2\n",
        "scalar.yaml": b"hello\n",
        "tabs.yaml": b"image:\tm.pgm\n",
        "unclosed.yaml": b"origin: [0, 0\n",
        "anchors.yaml": b"a: &x [0, 0, 0]\nimage: m.pgm\nresolution: 1\norigin: *x\nnegate: 0\noccupied_thresh: 0.65\nfree_thresh: 0.196\n",
        "empty.yaml": b"",
        "deep_nesting.yaml": b"image: " + b"[" * 3000 + b"\n",
        "alias_bomb.yaml": base + alias_bomb() + SEP + image,
        "alias_cycle.yaml": base.replace(b"[-10.0, -10.0, 0.0]", b"&o [0, 0, *o]") + SEP + image,
    }


def ascs():
    corner = (b"ncols 4\nnrows 3\nxllcorner 100.0\nyllcorner 200.0\ncellsize 2.5\nNODATA_value -9999\n"
              b"1 2 3 4\n5 -9999 7 8\n9.5 10 11 1e2\n")
    return {
        "corner.asc": corner,
        "center.asc": corner.replace(b"xllcorner", b"xllcenter").replace(b"yllcorner", b"yllcenter"),
        "crlf.asc": corner.replace(b"\n", b"\r\n"),
        "uppercase.asc": corner.replace(b"ncols", b"NCOLS").replace(b"nrows", b"NROWS").replace(b"cellsize", b"CELLSIZE"),
        "no_nodata.asc": b"ncols 2\nnrows 2\nxllcorner 0\nyllcorner 0\ncellsize 1\n1 2\n3 4\n",
        "one_line.asc": b"ncols 2\nnrows 2\nxllcorner 0\nyllcorner 0\ncellsize 1\nNODATA_value -1\n1 2 3 4\n",
        "nodata_all.asc": b"ncols 1\nnrows 1\nxllcorner 0\nyllcorner 0\ncellsize 1\nNODATA_value -1\n-1\n",
        "too_few.asc": b"ncols 3\nnrows 2\nxllcorner 0\nyllcorner 0\ncellsize 1\n1 2 3\n4\n",
        "too_many.asc": b"ncols 1\nnrows 1\nxllcorner 0\nyllcorner 0\ncellsize 1\n1 2\n",
        "huge.asc": b"ncols 1000000\nnrows 1000000\nxllcorner 0\nyllcorner 0\ncellsize 1\n1\n",
        "nan.asc": b"ncols 2\nnrows 1\nxllcorner 0\nyllcorner 0\ncellsize 1\nnan inf\n",
        "zero_cellsize.asc": b"ncols 1\nnrows 1\nxllcorner 0\nyllcorner 0\ncellsize 0\n1\n",
        "negative.asc": b"ncols -2\nnrows 1\nxllcorner 0\nyllcorner 0\ncellsize 1\n1 2\n",
        "missing_header.asc": b"ncols 1\n1\n",
        "empty.asc": b"",
        # With a .prj after the separator: read_asc converts degrees / feet to metres.
        "geographic_prj.asc": corner.replace(b"100.0", b"-105.5").replace(b"200.0", b"39.5").replace(b"2.5", b"0.000833333")
        + SEP + b'GEOGCS["GCS_WGS_1984",DATUM["D_WGS_1984",SPHEROID["WGS_1984",6378137.0,298.257223563]],'
                b'PRIMEM["Greenwich",0.0],UNIT["Degree",0.0174532925199433]]',
        "projected_prj.asc": corner + SEP + b'PROJCS["NAD_1983_UTM_Zone_13N",GEOGCS["GCS_North_American_1983",'
        b'DATUM["D_North_American_1983",SPHEROID["GRS_1980",6378137.0,298.257222101]],PRIMEM["Greenwich",0.0],'
        b'UNIT["Degree",0.0174532925199433]],PROJECTION["Transverse_Mercator"],PARAMETER["False_Easting",500000.0],'
        b'UNIT["Foot_US",0.3048006096012192]]',
        "esri_old_geographic.asc": corner.replace(b"200.0", b"89.99") + SEP + b"Projection    GEOGRAPHIC\nDatum         WGS84\nZunits        NO\nUnits         DD\n",
        "esri_old_feet.asc": corner + SEP + b"Projection UTM\nZone 13\nUnits FEET\n",
        "wkt2_prj.asc": corner + SEP + b'GEOGCRS["WGS 84",ELLIPSOID["WGS 84",6378137,298.257223563],ANGLEUNIT["degree",0.0174532925199433]]',
        "bad_latitude_prj.asc": corner.replace(b"200.0", b"95") + SEP + b'GEOGCS["x",UNIT["Degree",0.0174532925199433]]',
        "garbage_prj.asc": corner + SEP + b'PROJCS["unterminated,UNIT[',
    }


def csvs():
    return {
        "grid.csv": b"1,2,3\n4,5,6\n",
        "unobserved.csv": b"1.5,,3\n,-2e3,\n",
        "crlf.csv": b"1,2\r\n3,4\r\n",
        "no_final_newline.csv": b"0.25,0.5\n0.75,1",
        "single.csv": b"42\n",
        "ragged.csv": b"1,2,3\n4,5\n",
        "text.csv": b"1,abc\n2,3\n",
        "nan.csv": b"nan,inf\n-inf,1\n",
        "all_empty.csv": b",\n,\n",
        "spaces.csv": b" 1 , 2\n3 ,4 \n",
        "blank_line.csv": b"1,2\n\n3,4\n",
        "empty.csv": b"",
    }


def elevation_yamls():
    img16 = png(3, 2, 0, 16, [b"\x00\x00\x80\x00\xff\xff", b"\x00\x01\x12\x34\x00\x00"])
    img8 = png(2, 2, 0, 8, grey8(2, 2))
    base = b"image: e.png\nresolution: 0.5\norigin: [1.0, 2.0, 0.0]\nz_min: -1.5\nz_max: 10.0\n"
    return {
        "elev16.yaml": base + SEP + img16,
        "elev16_nodata.yaml": base + b"nodata: 0\n" + SEP + img16,
        "elev16_width_height.yaml": base + b"width: 3\nheight: 2\n" + SEP + img16,
        "elev16_wrong_width.yaml": base + b"width: 4\nheight: 2\n" + SEP + img16,
        "elev8.yaml": base + SEP + img8,
        "elev_yaw.yaml": base.replace(b"0.0]", b"0.7]") + SEP + img16,
        "elev_rgb.yaml": base + SEP + png(1, 1, 2, 8, [b"\x01\x02\x03"]),
        "elev_flat.yaml": base.replace(b"10.0", b"-1.5") + SEP + img16,
        "zmin_gt_zmax.yaml": base.replace(b"10.0", b"-5") + SEP + img16,
        "missing_zmax.yaml": b"image: e.png\nresolution: 0.5\norigin: [0, 0, 0]\nz_min: 0\n" + SEP + img16,
        "nodata_big.yaml": base + b"nodata: 70000\n" + SEP + img16,
        "pgm_image.yaml": base + SEP + b"P5\n1 1\n255\n\x05",
        "no_image.yaml": base,
        "bad_png.yaml": base + SEP + img16[:30],
        "nan_zmax.yaml": base.replace(b"10.0", b".nan") + SEP + img16,
        "deep_nesting.yaml": b"origin: " + b"{a: " * 2000 + b"\n" + SEP + img16,
        "alias_bomb.yaml": base + alias_bomb() + SEP + img16,
    }


def unity_raws():
    def sidecar(size, w, h, zmin=0.0, zmax=4.0, res=1.0, extra=""):
        return (f"format: unity_raw\nbyte_order: little\nsize: {size}\nwidth: {w}\nheight: {h}\n"
                f"resolution: {res}\norigin: [0.5, -2, 0.1]\nz_min: {zmin}\nz_max: {zmax}\n{extra}").encode()

    def raw(size, f):
        return b"".join(struct.pack("<H", f(x, y) & 0xFFFF) for y in range(size) for x in range(size))

    return {
        "raw3.raw": sidecar(3, 3, 3) + SEP + raw(3, lambda x, y: x * 1000 + y * 7),
        "raw5_padded.raw": sidecar(5, 4, 3) + SEP + raw(5, lambda x, y: (x + y) * 5000),
        "raw2.raw": sidecar(2, 2, 2) + SEP + raw(2, lambda x, y: 65535 * x),
        "raw_short.raw": sidecar(3, 3, 3) + SEP + raw(3, lambda x, y: 1)[:-3],
        "raw_long.raw": sidecar(3, 3, 3) + SEP + raw(3, lambda x, y: 1) + b"\x00\x00",
        "raw_odd_size.raw": sidecar(4, 4, 4) + SEP + raw(4, lambda x, y: 9),
        "raw_bigger_wh.raw": sidecar(3, 9, 9) + SEP + raw(3, lambda x, y: 9),
        "raw_huge_size.raw": sidecar(65537, 65537, 65537) + SEP + raw(3, lambda x, y: 9),
        "raw_no_sidecar.raw": SEP + raw(3, lambda x, y: 2),
        "raw_nan.raw": sidecar(3, 3, 3, zmax=".nan") + SEP + raw(3, lambda x, y: 2),
        "raw_nodata.raw": sidecar(3, 2, 3, extra="nodata: 0\n") + SEP + raw(3, lambda x, y: x * 30000),
        "raw_big_endian.raw": sidecar(2, 2, 2).replace(b"little", b"big") + SEP + raw(2, lambda x, y: 1),
        "raw_minimal_keys.raw": b"size: 3\nwidth: 3\nheight: 3\nresolution: 1\norigin: [0, 0, 0]\nz_min: 0\nz_max: 1\n" + SEP + raw(3, lambda x, y: 7),
        "raw_alias_bomb.raw": sidecar(3, 3, 3) + alias_bomb() + SEP + raw(3, lambda x, y: 7),
    }


def scenario_files():
    """The repository's own scenarios/*.yaml with comments and blank lines removed (to stay small)."""
    root = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "scenarios")
    out = {}
    if not os.path.isdir(root):
        return out
    for name in sorted(os.listdir(root)):
        if not name.endswith(".yaml"):
            continue
        lines = []
        with open(os.path.join(root, name), encoding="utf-8") as f:
            for line in f:
                line = line.rstrip("\n")
                if line.lstrip().startswith("#"):
                    continue
                at = line.find(" #")
                if at >= 0:
                    line = line[:at]
                line = line.rstrip()
                if line:
                    lines.append(line)
        out["repo_" + name] = ("\n".join(lines) + "\n").encode()
    return out


def speed_nav(limits):
    """A navigation section with two overlapping speed-limit zones and `limits` as their limits."""
    return (b"navigation:\n  goal: {x_m: 3.5, y_m: 1.5}\n  layers: [static_map, node_height, speed_limit]\n"
            b"  speed_limit:\n    zones:\n      - [[1, 0.5], [2, 0.5], [2, 2.5], [1, 2.5]]\n"
            b"      - [[1.5, 1], [3, 1], [2.2, 2]]\n    limits_mps: " + limits + b"\n")


def scenarios():
    world = b"world:\n  terrain:\n    generate: {kind: flat, size_m: [4, 3], resolution_m: 0.1}\n"
    sim = b"sim: {dt_s: 0.01, duration_s: 2.0, seed: 3}\n"
    cmds = b"commands:\n  - {duration_s: 1.0, vx_mps: 0.2}\n  - {until_s: 2.5, vy_mps: -0.1, wz_radps: 0.3}\n"
    robot = (b"robot:\n  drive: mecanum\n  half_track_m: 0.225\n  half_wheelbase_m: 0.2\n  wheel_radius_m: 0.076\n"
             b"  roller_angle_deg: 45\n  body_length_m: 0.55\n  body_width_m: 0.5\n  body_height_m: 0.25\n"
             b"  ground_clearance_m: 0.06\n  max_wheel_speed_radps: 10\n  max_wheel_accel_radps2: 20\n"
             b"  actuator_lag_s: 0.1\n  max_step_m: 0.05\n  start: {x_m: 0.5, y_m: 1.5, yaw_deg: 190}\n"
             b"vehicle: {friction: 0.6, rough_slip_sigma: 0.05}\n")
    obstacles = (b"world:\n  obstacles:\n"
                 b"    - {kind: box, name: b, position_m: [1, 1], size_m: [0.5, 0.4, 0.3], yaw_deg: 10, roll_deg: 1, pitch_deg: 2}\n"
                 b"    - {kind: cylinder, position_m: [2, 1, 0.1], radius_m: 0.2, height_m: 0.5, velocity_mps: [0.1, 0]}\n"
                 b"    - {kind: prism, position_m: [3, 1], yaw_deg: 90, base_width_m: 0.6, height_m: 0.1, length_m: 1, apex_offset_m: 0.1}\n"
                 b"    - {kind: sphere, position_m: [4, 1], radius_m: 0.3, appear_s: 1, disappear_s: 5}\n"
                 b"    - {kind: slope_step, position_m: [5, 1], width_m: 1.5, ramp_length_m: 0.5, ramp_height_m: 0.08,"
                 b" platform_length_m: 0.6, step_height_m: 0.04, step_length_m: 0.6, depth_m: 0.02}\n"
                 b"    - {kind: undulating_ground, position_m: [6, 1], count: 5, base_width_m: 0.5, height_m: 0.05, width_m: 1.5}\n"
                 b"    - {kind: round_convex, position_m: [7, 1], box_size_m: [1.2, 1.2, 0.04], radius_m: 0.4,"
                 b" cylinder_height_m: 0.04, depth_m: 0.02}\n"
                 b"    - {kind: gravel, position_m: [8, 1], length_m: 2, width_m: 1.5, count: 20, size_min_m: 0.01,"
                 b" size_max_m: 0.04, sphere_fraction: 0.5, embed: 0.3, seed: 7, follow_terrain: true}\n"
                 b"    - kind: box\n      name: mover\n      position_m: [9, 1]\n      size_m: [0.3, 0.3, 0.3]\n"
                 b"      waypoints:\n        - {t_s: 0, position_m: [9, 1]}\n        - {t_s: 2, position_m: [9, 2, 0.5]}\n")
    sensors = (b"sensors:\n  lidar:\n    preset: vlp16\n    horizontal_resolution_deg: 1.0\n    range_min_m: 0.5\n"
               b"    range_max_m: 30\n    rate_hz: 10\n    mount: {x_m: 0, y_m: 0, z_m: 0.41, roll_deg: 0, pitch_deg: 1, yaw_deg: 2}\n"
               b"    noise_sigma_m: 0.02\n    dropout: 0.01\n    self_filter: true\n    self_filter_margin_m: 0.05\n"
               b"  imu: {rate_hz: 100, yaw_rate_noise_sigma_radps: 0.002, yaw_rate_bias_radps: 0.0005, yaw_noise_sigma_rad: 0.001}\n"
               b"  encoders: {rate_hz: 50, ticks_per_rev: 1024, slip_sigma: 0.01}\n  bumper: false\n")
    custom_lidar = (b"sensors:\n  lidar:\n    beams: 180\n    scan_angle_deg: 270\n    elevations_deg: [10, 0, -10]\n"
                    b"    range_max_m: 8\n    self_filter: false\n")
    nav = (b"motion_mode: turn_then_drive\nnavigation:\n  goal: {x_m: 3.5, y_m: 2.5}\n  goal_tolerance_m: 0.15\n"
           b"  planner: dstar_lite\n  map:\n    resolution_m: 0.1\n    extent: paper\n    paper_min_size_m: 4\n"
           b"    mode: lidar_2d\n    barrier_distance_m: 0.45\n    max_step_m: 0.05\n    max_slope_deg: 15\n"
           b"    clear_margin_m: 0.05\n    hit_gain: 2\n    miss_loss: 1\n    evidence_max: 4\n    no_return_clear_m: 2.0\n"
           b"  follower:\n    cruise_speed_mps: 0.2\n    look_ahead_m: 0.3\n    pursuit_look_ahead_m: 0.6\n"
           b"    heading_gain: 2\n    max_yaw_rate_degps: 57.3\n    turn_tolerance_deg: 2.9\n    slow_down_distance_m: 0.3\n")
    outputs = (b"metrics:\n  reference_line_m: [[0, 1.5], [4, 1.5]]\n"
               b"outputs:\n  trajectory_every_n_steps: 5\n  point_clouds: {format: ply, every_n_scans: 2}\n")
    hills = (b"world:\n  terrain:\n    generate:\n      kind: hills\n      size_m: [10, 8]\n      resolution_m: 0.1\n"
             b"      origin_m: [-5, -4]\n      origin_yaw_deg: 30\n      seed: 5\n      amplitude: 1.0\n"
             b"      hills_per_100m2: 2\n      hill_height_m: [0.1, 0.5]\n      hill_sigma_m: [0.5, 2]\n"
             b"      roughness_m: 0.01\n      roughness_correlation_m: 0.2\n"
             b"      features:\n        - {kind: pit, centre_m: [1, 1], radius_m: 0.5, depth_m: 0.2}\n")
    road = (b"world:\n  terrain:\n    generate:\n      kind: road\n      size_m: [20, 20]\n      resolution_m: 0.05\n"
            b"      class: D\n      gd_n0_m3: 0.0\n      method: paper\n      n0_per_m: 0.1\n      band_per_m: [0.011, 2.83]\n"
            b"      waviness: 2.0\n      intervals: 64\n      directions: 16\n      blur_sigma_cells: 2.0\n"
            b"      features:\n        - {kind: mound, centre_m: [9.0, 10.6], radius_m: 1.5, depth_m: 0.6}\n")
    file_terrain = b"world:\n  terrain:\n    file: maps/ground.asc\n    features: [{kind: mound, centre_m: [0, 0], radius_m: 1, depth_m: 0.1}]\n"
    head = b"name: seed\ndescription: a hand-written seed\n"
    out = {
        "minimal.yaml": world + sim,
        "commands.yaml": head + world + cmds,
        "robot.yaml": world + robot + sim + cmds,
        "differential.yaml": world + b"robot: {drive: differential}\n" + sim,
        "ackermann.yaml": world + b"robot: {drive: ackermann, max_steer_deg: 30, max_steer_rate_degps: 60}\n" + cmds,
        "obstacles.yaml": obstacles + sim,
        "sensors.yaml": world + sensors + sim,
        "custom_lidar.yaml": world + custom_lidar + sim,
        "planar_preset.yaml": world + b"sensors:\n  lidar: {preset: hokuyo_utm30lx}\n" + sim,
        "navigation.yaml": world + robot + sensors + sim + nav,
        "nav_minimal.yaml": world + sim + b"motion_mode: auto\nnavigation: {goal: {x_m: 1, y_m: 1}}\n",
        "motion_modes.yaml": world + sim + b"motion_mode: holonomic\n",
        "pure_pursuit.yaml": world + sim + b"motion_mode: pure_pursuit\nnavigation: {goal: {x_m: 1, y_m: 1}, map: {mode: nodes_3d}}\n",
        "outputs.yaml": world + sensors + sim + outputs,
        "pcd.yaml": world + sensors + sim + b"outputs: {point_clouds: {format: pcd}}\n",
        "hills.yaml": hills + sim,
        "road.yaml": road + sim,
        "file_terrain.yaml": file_terrain + sim,
        "no_world.yaml": sim,
        "empty_sections.yaml": world + b"sensors:\n  imu:\n  encoders:\n" + sim,
        # Invalid on purpose.
        "unknown_key.yaml": world + sim + b"colour: red\n",
        "duplicate_key.yaml": world + sim + b"sim: {duration_s: 1}\n",
        "nav_with_commands.yaml": world + cmds + b"navigation: {goal: {x_m: 1, y_m: 1}}\n",
        "bad_motion_mode.yaml": world + sim + b"motion_mode: sideways\n",
        "no_duration.yaml": world,
        "nan_goal.yaml": world + sim + b"navigation: {goal: {x_m: .nan, y_m: 1}}\n",
        "command_order.yaml": world + b"commands:\n  - {until_s: 2}\n  - {until_s: 1}\n",
        "both_duration_until.yaml": world + b"commands: [{duration_s: 1, until_s: 2}]\n",
        "huge_terrain.yaml": b"world:\n  terrain:\n    generate: {kind: flat, size_m: [100000, 100000], resolution_m: 0.001}\n" + sim,
        "big_terrain.yaml": b"world:\n  terrain:\n    generate: {kind: hills, size_m: [2000, 2000], resolution_m: 0.05}\n" + sim,
        "big_gravel.yaml": b"world:\n  obstacles:\n    - {kind: gravel, position_m: [0, 0], count: 100000}\n" + sim,
        "fine_lidar.yaml": world + b"sensors:\n  lidar: {preset: hdl64e, horizontal_resolution_deg: 0.0001}\n" + sim,
        "both_terrains.yaml": b"world:\n  terrain: {file: a.asc, generate: {kind: flat, size_m: [1, 1]}}\n" + sim,
        "velocity_and_waypoints.yaml": b"world:\n  obstacles:\n    - {kind: sphere, position_m: [0, 0], radius_m: 1,"
                                       b" velocity_mps: [1, 0], waypoints: [{t_s: 0, position_m: [0, 0]}]}\n" + sim,
        "duplicate_names.yaml": b"world:\n  obstacles:\n    - {kind: sphere, name: a, position_m: [0, 0], radius_m: 1}\n"
                                b"    - {kind: sphere, name: a, position_m: [1, 0], radius_m: 1}\n" + sim,
        "anchors.yaml": b"world:\n  obstacles:\n    - &o {kind: sphere, position_m: [0, 0], radius_m: 1}\n    - *o\n" + sim,
        "flow.yaml": b"{world: {}, sim: {duration_s: 1}, commands: [{duration_s: 1}]}\n",
        "list.yaml": b"- world\n- sim\n",
        "scalar.yaml": b"scenario\n",
        "empty.yaml": b"",
        "tabs.yaml": b"world:\t{}\n",
        "deep_nesting.yaml": b"world: " + b"[" * 3000 + b"\n",
        "alias_bomb.yaml": alias_bomb() + sim,
        "alias_cycle.yaml": b"world:\n  obstacles: &o [*o]\n" + sim,
        # Speed-limit zones: a list of numbers beside the polygons; then each way it can be wrong.
        "speed_zones.yaml": world + sim + speed_nav(b"[0.3, 0.1]"),
        "speed_zones_mismatch.yaml": world + sim + speed_nav(b"[0.3]"),
        "speed_zones_zero.yaml": world + sim + speed_nav(b"[0.3, 0]"),
        "speed_zones_nested.yaml": world + sim + speed_nav(b"[0.3, [0.1]]"),
        "speed_zones_scalar.yaml": world + sim + speed_nav(b"0.3"),
        "speed_zones_empty.yaml": world + sim + speed_nav(b"[]"),
    }
    out.update(scenario_files())
    return out


def carmen_logs():
    flaser = b"FLASER 3 1.00 2.50 81.91 0.0 0.0 0.0 1.0 2.0 0.5 100.100000 host 0.2\n"
    return {
        "carmen.clf": b"# CARMEN Logfile\nPARAM robot_frontlaser_offset 0.25 nohost 0.0\n"
        + b"ODOM 1.0 2.0 0.5 0.3 0.1 0.0 100.000001 host 0.1\n" + flaser
        + b"RAWLASER1 0 -1.5708 3.1416 0.0174533 30.0 0.01 0 2 4.0 5.0 0 100.2 host 0.3\n"
        + b"ROBOTLASER1 0 -1.0 2.0 0.5 20.0 0.01 0 3 1.5 2.5 3.5 1 9.0 0.1 0.2 0.3 1.0 2.0 0.4 0.5 0.6 0.1 0.1 0.2 100.3 host 0.4\n"
        + b"TRUEPOS 5.0 6.0 0.7 1.0 2.0 0.5 100.4 host 0.5\nNMEA $GPGGA\n",
        "flaser_repeat.clf": flaser * 12,
        "odomscan.txt": b"# extract\nODOMETRY 1.000000 0.5 0.25 0.1 0.2 0.0\nLASERSCAN 1.100000 3 1.00 2.00 3.00\n"
        + b"ODOMETRY 0.900000 0.6 0.25 3.1 0.2 0.0\n",
        "bad_count.clf": b"FLASER 99999 1.0\n",
        "crlf.clf": flaser.replace(b"\n", b"\r\n"),
        "resolution_zero.clf": b"RAWLASER1 0 0 3 0 10 0.01 0 2 1 2 0 1.0 h 0\n",
        "negative_range.clf": b"FLASER 3 1 -1 2 0 0 0 0 0 0 1.0 h 0\n",
        "far_pose.clf": b"ODOM 1e19 0 0 0 0 0 1.0 h 0\n",
        "stray_above_saturation.clf": flaser * 12 + flaser.replace(b"81.91", b"81.92"),
        "float_overflow.clf": flaser.replace(b"81.91", b"1e308"),
        "odometry_only.clf": b"ODOM 0 0 0 0 0 0 1.0 h 1.0\nODOM x 0 0 0 0 0 2.0 h 2.0\n",
        "odometry_only.txt": b"ODOMETRY 1.0 0 0 0 0 0\nODOMETRY 2.0 x 0 0 0 0\n",
        "bare_odom.clf": b"ODOM 0 0 0 0 0 0 1\n" * 64,
    }


def ros_bags():
    """Bags written from the format description (plain and bzip2 chunks; LZ4 needs a module
    Python lacks: the unit tests cover it)."""
    import bz2

    def field(name, value):
        return struct.pack("<I", len(name) + 1 + len(value)) + name + b"=" + value

    def record(header, data):
        return struct.pack("<I", len(header)) + header + struct.pack("<I", len(data)) + data

    def header(sec, nsec, frame):
        return struct.pack("<III", 0, sec, nsec) + struct.pack("<I", len(frame)) + frame

    def connection(cid, topic, kind):
        h = field(b"op", b"\x07") + field(b"conn", struct.pack("<I", cid)) + field(b"topic", topic)
        return record(h, field(b"topic", topic) + field(b"type", kind) + field(b"md5sum", b"0" * 32))

    def message(cid, sec, data):
        h = field(b"op", b"\x02") + field(b"conn", struct.pack("<I", cid)) + field(b"time", struct.pack("<II", sec, 0))
        return record(h, data)

    scan = header(10, 500, b"laser") + struct.pack("<7f", -1.0, 1.0, 0.5, 0.0, 0.0, 0.1, 30.0)
    scan += struct.pack("<I5f", 5, 1.0, 2.0, 30.0, 4.0, 5.0) + struct.pack("<I", 0)
    odom = header(10, 0, b"odom") + struct.pack("<I", 9) + b"base_link" + struct.pack("<7d", 1, 2, 0, 0, 0, 0.2, 0.98)
    odom += struct.pack("<36d", *([0.0] * 36)) + struct.pack("<6d", 0.3, 0, 0, 0, 0, 0.1) + struct.pack("<36d", *([0.0] * 36))
    tf = struct.pack("<I", 1) + header(0, 0, b"base_link") + struct.pack("<I", 5) + b"laser" + struct.pack("<7d", 0.04, 0, 0, 0, 0, 0, 1)
    inner = (connection(0, b"/tf_static", b"tf2_msgs/TFMessage") + message(0, 1, tf)
             + connection(1, b"/scan", b"sensor_msgs/LaserScan") + connection(2, b"/odom", b"nav_msgs/Odometry")
             + message(2, 10, odom) + message(1, 10, scan))

    def bag_of(content):
        h = field(b"op", b"\x05") + field(b"compression", b"none") + field(b"size", struct.pack("<I", len(content)))
        bh = field(b"op", b"\x03") + field(b"index_pos", struct.pack("<Q", 0)) + field(b"conn_count", struct.pack("<I", 0))
        bh += field(b"chunk_count", struct.pack("<I", 0))
        return b"#ROSBAG V2.0\n" + record(bh, b" " * 64) + record(h, content)

    def bag(compression, stored):
        h = field(b"op", b"\x05") + field(b"compression", compression) + field(b"size", struct.pack("<I", len(inner)))
        bh = field(b"op", b"\x03") + field(b"index_pos", struct.pack("<Q", 0)) + field(b"conn_count", struct.pack("<I", 0))
        bh += field(b"chunk_count", struct.pack("<I", 0))
        return b"#ROSBAG V2.0\n" + record(bh, b" " * 64) + record(h, stored)

    # A 3D recording: two PointCloud2 rows of float32 x, y, z after an intensity, one NaN point.
    fields = b"".join(struct.pack("<I", len(n)) + n + struct.pack("<IBI", off, 7, 1)
                      for n, off in ((b"intensity", 0), (b"x", 4), (b"y", 8), (b"z", 12)))
    pts = [(1.0, 2.0, 3.0), (4.0, 5.0, -1.0), (float("nan"), 0.0, 0.0), (7.0, 8.0, 9.0)]
    data = b"".join(struct.pack("<4f", 1.0, *p) for p in pts)
    cloud = header(10, 0, b"velodyne") + struct.pack("<II", 2, 2) + struct.pack("<I", 4) + fields
    cloud += struct.pack("<BII", 0, 16, 32) + struct.pack("<I", len(data)) + data + b"\x00"
    tf3 = struct.pack("<I", 1) + header(0, 0, b"base_link") + struct.pack("<I", 8) + b"velodyne"
    tf3 += struct.pack("<7d", 0.1, 0, 0.55, 0, 0, 0, 1)
    points = (connection(0, b"/tf_static", b"tf2_msgs/TFMessage") + message(0, 1, tf3)
              + connection(1, b"/points", b"sensor_msgs/PointCloud2") + connection(2, b"/odom", b"nav_msgs/Odometry")
              + message(2, 10, odom) + message(1, 10, cloud))
    # Faulty scans: an increment of 0 with five beams, angle_min above angle_max, a negative reading.
    def scan_bag(layout, readings):
        bad = header(10, 500, b"laser") + struct.pack("<7f", *layout) + struct.pack("<I", len(readings))
        bad += struct.pack(f"<{len(readings)}f", *readings) + struct.pack("<I", 0)
        return bag_of(connection(1, b"/scan", b"sensor_msgs/LaserScan") + message(1, 10, bad))

    return {
        "scan_increment_zero.bag": scan_bag((-1.0, 1.0, 0.0, 0.0, 0.0, 0.1, 30.0), (1.0, 2.0, 3.0, 4.0, 5.0)),
        "scan_angles_reversed.bag": scan_bag((1.0, -1.0, 0.5, 0.0, 0.0, 0.1, 30.0), (1.0, 2.0, 3.0, 4.0, 5.0)),
        "scan_negative_range.bag": scan_bag((-1.0, 1.0, 0.5, 0.0, 0.0, 0.1, 30.0), (1.0, -2.0, 3.0, 4.0, 5.0)),
        "points.bag": bag_of(points),
        "plain.bag": bag(b"none", inner),
        "bz2.bag": bag(b"bz2", bz2.compress(inner, 9)),
        "unknown_compression.bag": bag(b"zip", inner),
        "magic_only.bag": b"#ROSBAG V2.0\n",
    }


class Cdr:
    """Little-endian plain CDR (XCDR1): fields aligned to their size after the 4-byte header."""

    def __init__(self):
        self.b = bytearray(b"\x00\x01\x00\x00")

    def put(self, fmt, *v):
        size = struct.calcsize("<" + fmt.lstrip("0123456789"))
        while (len(self.b) - 4) % size:
            self.b.append(0)
        self.b += struct.pack("<" + fmt, *v)
        return self

    def string(self, s):
        self.put("I", len(s) + 1)
        self.b += s + b"\x00"
        return self

    def header(self, sec, nsec, frame):
        return self.put("i", sec).put("I", nsec).string(frame)


def ros2_messages():
    scan = Cdr().header(10, 500, b"laser").put("7f", -1.0, 1.0, 0.5, 0.0, 0.0, 0.1, 30.0)
    scan.put("I", 5).put("5f", 1.0, 2.0, 30.0, 4.0, 5.0).put("I", 0)
    odom = Cdr().header(10, 0, b"odom").string(b"base_link").put("7d", 1, 2, 0, 0, 0, 0.2, 0.98)
    odom.put("36d", *([0.0] * 36)).put("6d", 0.3, 0, 0, 0, 0, 0.1).put("36d", *([0.0] * 36))
    tf = Cdr().put("I", 1).header(0, 0, b"base_link").string(b"laser").put("7d", 0.04, 0, 0, 0, 0, 0, 1)
    imu = Cdr().header(10, 0, b"imu").put("4d", 0, 0, 0, 1).put("9d", *([0.0] * 9)).put("3d", 0, 0, 0.1)
    imu.put("9d", *([0.0] * 9)).put("3d", 0, 0, 9.8).put("9d", *([0.0] * 9))
    pose = Cdr().header(10, 0, b"map").put("7d", 1, 2, 0, 0, 0, 0, 1)
    pose_cov = Cdr().header(10, 0, b"map").put("7d", 1, 2, 0, 0, 0, 0, 1).put("36d", *([0.0] * 36))
    cloud = Cdr().header(10, 0, b"lidar").put("I", 1).put("I", 2).put("I", 3)
    for name, off in ((b"x", 0), (b"y", 4), (b"z", 8)):
        cloud.string(name).put("I", off).put("B", 7).put("I", 1)
    cloud.put("B", 0).put("I", 12).put("I", 24).put("I", 24).put("6f", 1, 2, 3, 4, 5, 6).put("B", 1)
    return {"scan": bytes(scan.b), "odom": bytes(odom.b), "imu": bytes(imu.b), "tf": bytes(tf.b), "pose": bytes(pose.b),
            "pose_cov": bytes(pose_cov.b), "cloud": bytes(cloud.b)}


def cdrs():
    """fuzz_cdr: a type byte (fuzz_drivers.hpp's order), then the message."""
    order = ["scan", "odom", "imu", "tf", "pose", "pose_cov", "cloud"]
    m = ros2_messages()
    return {f"{name}.cdr": bytes([i]) + m[name] for i, name in enumerate(order)}


MCAP_TYPES = {"scan": (b"/scan", b"sensor_msgs/msg/LaserScan"), "odom": (b"/odom", b"nav_msgs/msg/Odometry"),
              "tf": (b"/tf_static", b"tf2_msgs/msg/TFMessage"), "imu": (b"/imu", b"sensor_msgs/msg/Imu")}


def mcaps():
    """MCAP files written from the specification: chunked (plain) with message indexes and a
    summary, unchunked without summary, and one cut short. Compressed chunks need modules Python
    lacks; the unit tests and the converter cover them."""

    def rec(op, body):
        return struct.pack("<BQ", op, len(body)) + body

    def s(b):
        return struct.pack("<I", len(b)) + b

    m = ros2_messages()
    magic = b"\x89MCAP0\r\n"
    header = rec(1, s(b"ros2") + s(b"seed"))
    defs, msgs = b"", []
    for i, name in enumerate(("tf", "odom", "scan", "imu")):
        topic, kind = MCAP_TYPES[name]
        defs += rec(3, struct.pack("<H", i + 1) + s(kind) + s(b"ros2msg") + s(b""))
        defs += rec(4, struct.pack("<HH", i, i + 1) + s(topic) + s(b"cdr") + s(b""))
        msgs.append(rec(5, struct.pack("<HIQQ", i, 0, 10 + i, 10 + i) + m[name]))
    unchunked = magic + header + defs + b"".join(msgs) + rec(15, struct.pack("<I", 0))
    unchunked += rec(2, struct.pack("<QQI", 0, 0, 0)) + magic
    records = defs + b"".join(msgs)
    offsets, at = {}, len(defs)
    for i, r in enumerate(msgs):
        offsets[i] = at
        at += len(r)
    chunk_body = struct.pack("<QQQI", 10, 13, len(records), zlib.crc32(records)) + s(b"") + struct.pack("<Q", len(records)) + records
    data = magic + header
    chunk_at = len(data)
    data += rec(6, chunk_body)
    chunk_len = len(data) - chunk_at
    index_at = {}
    for i in range(4):
        index_at[i] = len(data)
        data += rec(7, struct.pack("<H", i) + struct.pack("<I", 16) + struct.pack("<QQ", 10 + i, offsets[i]))
    index_len = len(data) - index_at[0]
    data += rec(15, struct.pack("<I", 0))
    summary_start = len(data)
    data += defs
    counts = b"".join(struct.pack("<HQ", i, 1) for i in range(4))
    data += rec(11, struct.pack("<QHIIIIQQ", 4, 4, 4, 0, 0, 1, 10, 13) + s(counts))
    mio = b"".join(struct.pack("<HQ", i, index_at[i]) for i in range(4))
    data += rec(8, struct.pack("<QQQQ", 10, 13, chunk_at, chunk_len) + s(mio) + struct.pack("<Q", index_len) + s(b"")
                + struct.pack("<QQ", len(records), len(records)))
    footer = struct.pack("<BQQQ", 2, 20, summary_start, 0)
    crc = zlib.crc32(data[summary_start:] + footer)
    chunked = data + footer + struct.pack("<I", crc) + magic
    out = {"chunked.mcap": chunked, "unchunked.mcap": unchunked, "cut.mcap": chunked[: len(chunked) * 2 // 3],
           "magic_only.mcap": magic}
    here = os.path.dirname(os.path.abspath(__file__))
    for name in ("mcap/talker/talker.mcap", "mcap/cdr_test/cdr_test_0.mcap"):
        with open(os.path.join(here, "..", "..", "tests", "data", "rosbag2", name), "rb") as f:
            out["rosbag2-" + os.path.basename(name)] = f.read()
    return out


def sqlites():
    """rosbag2 SQLite3 databases made with Python's sqlite3 (a temporary file), and rosbag2's own."""
    import sqlite3
    import tempfile

    m = ros2_messages()
    out = {}
    with tempfile.TemporaryDirectory() as d:
        path = os.path.join(d, "bag.db3")
        db = sqlite3.connect(path)
        db.executescript("PRAGMA page_size=512;"
                         "CREATE TABLE topics(id INTEGER PRIMARY KEY, name TEXT NOT NULL, type TEXT NOT NULL,"
                         " serialization_format TEXT NOT NULL, offered_qos_profiles TEXT NOT NULL);"
                         "CREATE TABLE messages(id INTEGER PRIMARY KEY, topic_id INTEGER NOT NULL, timestamp INTEGER NOT NULL,"
                         " data BLOB NOT NULL);")
        for i, name in enumerate(("tf", "odom", "scan", "imu")):
            topic, kind = MCAP_TYPES[name]
            db.execute("INSERT INTO topics VALUES (?, ?, ?, 'cdr', '')", (i + 1, topic.decode(), kind.decode()))
            db.execute("INSERT INTO messages (topic_id, timestamp, data) VALUES (?, ?, ?)", (i + 1, 10 + i, m[name]))
        db.commit()
        db.close()
        with open(path, "rb") as f:
            out["bag.db3"] = f.read()
    here = os.path.dirname(os.path.abspath(__file__))
    with open(os.path.join(here, "..", "..", "tests", "data", "rosbag2", "sqlite3", "cdr_test", "cdr_test_0.db3"), "rb") as f:
        out["rosbag2-cdr_test_0.db3"] = f.read()
    return out


def point_clouds():
    xyz = [(1.5, -2.25, 0.125), (0.0, 0.0, 0.0), (-3.5, 4.75, 10.0)]
    header = "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH 3\nHEIGHT 1\nPOINTS 3\n"
    binary = b"".join(struct.pack("<fff", *p) for p in xyz)
    soa = b"".join(struct.pack("<fff", *[p[a] for p in xyz]) for a in range(3))
    lzf = bytes([31]) + soa[:32] + bytes([len(soa) - 33]) + soa[32:]  # two literal runs (at most 32 bytes each)
    ply_head = "ply\nformat {} 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nend_header\n"
    return {
        "ascii.pcd": (header + "DATA ascii\n" + "".join("%g %g %g\n" % p for p in xyz)).encode(),
        "binary.pcd": (header + "DATA binary\n").encode() + binary,
        "compressed.pcd": (header + "DATA binary_compressed\n").encode() + struct.pack("<II", len(lzf), len(soa)) + lzf,
        "ascii.ply": (ply_head.format("ascii") + "".join("%g %g %g\n" % p for p in xyz)).encode(),
        "binary.ply": ply_head.format("binary_little_endian").encode() + binary,
        "big.ply": ply_head.format("binary_big_endian").encode() + b"".join(struct.pack(">fff", *p) for p in xyz),
        "kitti.bin": b"".join(struct.pack("<ffff", *p, 0.5) for p in xyz),
        "lzf_backref": struct.pack("<I", 9) + b"\x02abc\x80\x02",
    }


def sweep_files():
    """The repository's examples/sweeps/*.yaml without comments, and small valid and invalid sweeps."""
    root = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "examples", "sweeps")
    out = {}
    for name in sorted(os.listdir(root)) if os.path.isdir(root) else []:
        if name.endswith(".yaml"):
            with open(os.path.join(root, name), "rb") as f:
                lines = [l for l in f.read().split(b"\n") if l.strip() and not l.lstrip().startswith(b"#")]
            out["example-" + name] = b"\n".join(lines) + b"\n"
    out.update({
        "minimal.yaml": b"command: [plan, --seed, '{s}']\naxes: {s: {from: 0, count: 3}}\n",
        "zip.yaml": b"command: [plan, --start, '{q.a}', --goal, '{q.b}', --out, '{out}/x']\n"
                    b"axes:\n  q: [{a: '1,1', b: '2,2'}, {a: '3,3', b: '4,4'}]\n  k.x: [1, 2]\n",
        "range_real.yaml": b"command: [sim, s.yaml]\naxes: {a.b: {from: -0.5, to: 0.75, step: 0.25}}\n"
                           b"metrics: {m: /m, t: {pointer: /t, timing: true, when: /ok}}\n"
                           b"summary: {group_by: [a.b], baseline: '0.25'}\n"
                           b"plots: [{metric: m, x: a.b, error: sd}]\n",
        "braces.yaml": b"command: [plan, '{{literal}}', 'x{v}y']\naxes: {v: ['{a}', '}}{{']}\nresult: out.json\n",
        "glob.yaml": b"command: [plan, --map, '{map}']\naxes: {map: {glob: ['*.map', 'm/*.yaml']}}\n",
        "unknown_key.yaml": b"command: [plan]\naxes: {s: [1]}\nbogus: 1\n",
        "unused_axis.yaml": b"command: [plan]\naxes: {s: [1, 2]}\n",
        "huge.yaml": b"command: [plan, '{a}{b}']\naxes: {a: {from: 0, count: 100000}, b: {from: 0, count: 100000}}\n",
        "bad_pointer.yaml": b"command: [plan, '{s}']\naxes: {s: [1]}\nmetrics: {m: 'cost'}\n",
    })
    return out


TARGETS = {
    "fuzz_movingai_map": maps,
    "fuzz_movingai_scen": scens,
    "fuzz_pgm": pgms,
    "fuzz_png": pngs,
    "fuzz_ros_yaml": ros_yamls,
    "fuzz_asc": ascs,
    "fuzz_elevation_csv": csvs,
    "fuzz_elevation_yaml": elevation_yamls,
    "fuzz_unity_raw": unity_raws,
    "fuzz_scenario": scenarios,
    "fuzz_carmen_log": carmen_logs,
    "fuzz_ros_bag": ros_bags,
    "fuzz_point_cloud": point_clouds,
    "fuzz_sweep_file": sweep_files,
    "fuzz_mcap": mcaps,
    "fuzz_rosbag2_sqlite": sqlites,
    "fuzz_cdr": cdrs,
}


def main():
    root = sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "corpus")
    only = set(sys.argv[2:])
    for target, make in TARGETS.items():
        if only and target not in only:
            continue
        out = os.path.join(root, target)
        os.makedirs(out, exist_ok=True)
        for name, data in make().items():
            # libFuzzer names corpus files by SHA-1; seeds keep a readable prefix instead.
            path = os.path.join(out, f"seed-{name}")
            with open(path, "wb") as f:
                f.write(data)
        print(f"{target}: {len(make())} seeds in {out}")


if __name__ == "__main__":
    main()
