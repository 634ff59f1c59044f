// The outline core's basic types, shared by the triangulation (delaunay.hpp), the alpha shape (alpha.hpp)
// and the pipeline (outline.hpp), so that the parts include only what they use.
#pragma once

#include <cstdint>
#include <stdexcept>
#include <vector>

namespace hg::outline {

struct Vec2 {
  double x = 0, y = 0;
};

// Point location scheme of the Bowyer-Watson insertion (paper section 3.1).
enum class Mode { Ordinary, DS, DSHI };
// Insertion order: as given (scan order), or sorted along a space-filling curve first. Brio: biased
// randomized insertion order (rounds growing 16-fold, each along the Hilbert curve): points land inside
// the current mesh, so cavities stay small (about 4.4 triangles instead of 6.8 on camera grids).
enum class Order { AsIs, Hilbert, Brio };

// Bad input (fewer than 3 distinct finite points, all collinear, out of the exact range, bad option):
// message says what and where. Non-finite points are no error: they are skipped and counted.
struct OutlineError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

struct Loop {
  bool hole = false;  // outer loops counter-clockwise, holes clockwise
  double area = 0;    // positive
  double perimeter = 0;
  std::vector<Vec2> points;                // closing edge last -> first implicit
  std::vector<std::uint32_t> point_index;  // index of each point in the input as given (skipped points included)
};

}  // namespace hg::outline
