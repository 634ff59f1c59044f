#pragma once
// The product's colours, one meaning each, as the operator station draws them (station/web/scene.js and
// top.js; tests/tools/palette_test.py keeps the two equal). overview.png, hg-outline's pictures and the
// Foxglove scene draw with these, so that red is an unreached edge everywhere and never a hole. RGB.
#include <cstdint>

namespace hg::outline_io::palette {

inline constexpr std::uint32_t kBackground = 0x10161d, kCloud = 0x3d5a80, kText = 0xffffff;
inline constexpr std::uint32_t kOuter = 0xffffff, kHole = 0x40c4ff, kEdge = 0xff40ff, kUnreached = 0xff1744;
// By grind_path_t kind: approach, lead-in, grind, lead-out, retract, travel.
inline constexpr std::uint32_t kKindColours[] = {0x7f8fa6, 0x43a047, 0xff9800, 0x00acc1, 0x8e24aa, 0xbbbbbb};

// The colour of a waypoint kind; text colour for a kind out of range.
constexpr std::uint32_t kind_colour(int kind) { return kind >= 0 && kind < 6 ? kKindColours[kind] : kText; }

}  // namespace hg::outline_io::palette
