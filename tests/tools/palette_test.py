#!/usr/bin/env python3
"""One meaning per colour: the product's C++ palette (outline_io/palette.hpp: overview.png, hg-outline's
pictures, the Foxglove scene) is the station's (station/web/scene.js and top.js): the same people read the
station's views, make run's overview.png and a Foxglove panel of the same cell. Read from both sources as
written."""
import os
import re
import unittest

SRC = os.environ.get("HG_SOURCE_DIR", os.path.abspath(os.path.join(os.path.dirname(__file__), "..", "..")))


def read(path):
    with open(os.path.join(SRC, path)) as f:
        return f.read()


def hex_list(text):
    return [int(v, 16) for v in re.findall(r"0x([0-9a-fA-F]{6})", text)]


def station_palette():
    scene, top = read("station/web/scene.js"), read("station/web/top.js")
    kinds = re.search(r"KIND_COLOURS\s*=\s*\[([^\]]*)\]", scene).group(1)
    palette = {"kinds": hex_list(kinds)}
    for name in ("UNREACHED", "HOLE", "OUTER", "EDGE"):
        palette[name.lower()] = int(re.search(name + r"\s*=\s*0x([0-9a-fA-F]{6})", scene).group(1), 16)
    draw_static = top[top.index("function drawStatic"):]
    fills = re.findall(r'fillStyle\s*=\s*"#([0-9a-fA-F]{6})"', draw_static)
    palette["background"], palette["cloud"] = int(fills[0], 16), int(fills[1], 16)
    return palette


def product_palette():
    cpp = read("outline_io/palette.hpp")
    named = {m.group(1): int(m.group(2), 16) for m in re.finditer(r"\bk([A-Z][a-z]+)\s*=\s*0x([0-9a-fA-F]{6})", cpp)}
    kinds = re.search(r"kKindColours\[\]\s*=\s*\{([^}]*)\}", cpp).group(1)
    return {"kinds": hex_list(kinds), "unreached": named["Unreached"], "hole": named["Hole"],
            "outer": named["Outer"], "edge": named["Edge"], "background": named["Background"], "cloud": named["Cloud"]}


class Palette(unittest.TestCase):
    def test_the_products_pictures_draw_in_the_stations_colours(self):
        station, overview = station_palette(), product_palette()
        self.assertEqual(len(station["kinds"]), 6, "one colour per waypoint kind of grind_path_t")
        for key in station:
            with self.subTest(colour=key):
                self.assertEqual(overview[key], station[key])

    def test_no_two_meanings_share_a_colour(self):
        station = station_palette()
        singles = [station[k] for k in ("unreached", "hole", "outer", "edge", "background", "cloud")]
        everything = singles + station["kinds"]
        self.assertEqual(len(set(everything)), len(everything), [hex(c) for c in everything])


if __name__ == "__main__":
    unittest.main()
