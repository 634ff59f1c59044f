// Private OpenNI2 stream properties of the virtual device. OpenNI2 itself only knows the fields of view,
// which fix fx and fy but not the principal point; a reader that knows this id (the openni2 source) gets
// the exact one, others assume the image centre.
#pragma once

namespace hg::sim::virtual_device {

// double[2] = {cx, cy} in pixels. Read-only. Value chosen in the vendor-private range ("HG" + 1).
inline constexpr int kStreamPropertyPrincipalPoint = 0x48470001;

}  // namespace hg::sim::virtual_device
