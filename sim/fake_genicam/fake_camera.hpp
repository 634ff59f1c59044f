// A fake GigE Vision 3-D camera: Aravis's GigE Vision fake camera (GVCP control, GVSP streaming) with our
// GenICam description (hg-fake-3d-camera.xml) and a fill callback that serves the scene renderer's depth
// as Coord3D_C16 range images (or Coord3D_ABC32f clouds, when the client selects that pixel format) with
// the given Scan3d scale, offset and pinhole of the camera profile.
// For tests and hg-fake-genicam only: bind it to 127.0.0.1 inside a network namespace (tests/netns.sh).
#pragma once

#include <atomic>
#include <cstdint>
#include <memory>
#include <mutex>
#include <string>

#include "sim/scene/scene.hpp"

namespace hg::sim {

struct FakeGenicamOptions {
  std::string interface = "127.0.0.1";  // address or interface name Aravis binds the fake device to
  std::string serial = "HG3D-0001";
  std::string xml_path;  // empty: the hg-fake-3d-camera.xml of the source tree
  SceneSpec scene;
  CameraProfile profile;   // image size, focal length (fx is served), principal point
  double scale_mm = 0.05;  // Scan3dCoordinateScale: millimetres per raw step
  double offset_mm = 0.0;  // Scan3dCoordinateOffset
  double frame_rate = 10;  // free-running frames per second
  // >= 0: every frame is the scene rendered at this index (its noise included); < 0: frame n of the device
  // is the rendering at index n, the sequence the `synthetic` source delivers.
  std::int64_t fixed_frame_index = -1;
};

class FakeGenicamCamera {
 public:
  // Throws std::runtime_error when Aravis cannot start the device (e.g. the address is not there).
  explicit FakeGenicamCamera(FakeGenicamOptions options);
  ~FakeGenicamCamera();
  FakeGenicamCamera(const FakeGenicamCamera&) = delete;
  FakeGenicamCamera& operator=(const FakeGenicamCamera&) = delete;

  const FakeGenicamOptions& options() const { return options_; }
  std::int64_t frames_served() const { return served_; }
  // The device id Aravis's discovery lists it by ("<vendor>-<model>-<serial>").
  std::string device_id() const { return "Aravis-Fake-" + options_.serial; }
  // Writes one of the fake camera's registers (tests: change Width behind the client's back, ...).
  void write_register(std::uint32_t address, std::uint32_t value);
  std::uint32_t read_register(std::uint32_t address) const;
  // Fraction of GVSP packets the device drops (Aravis's fake camera sends no resends: frames with a lost
  // packet arrive incomplete at the client).
  void set_packet_loss(double ratio);
  // Raw value the fill callback serves for a depth in metres (0 when no data or out of range).
  std::uint16_t raw_of(double metres) const;

 private:
  static void fill(void* buffer, void* self, std::uint32_t, std::uint32_t, std::uint32_t);
  void write_double(std::uint32_t address, double value);
  void fill_abc32f_row(const std::uint16_t* depth, int row, float* xyz) const;

  FakeGenicamOptions options_;
  void* gv_ = nullptr;  // ArvGvFakeCamera*
  std::atomic<std::int64_t> served_{0};
};

// Register addresses of the Scan3d values in hg-fake-3d-camera.xml.
namespace fake_genicam_reg {
constexpr std::uint32_t kScale = 0x400, kOffset = 0x408, kInvalid = 0x410, kFocal = 0x418, kPpu = 0x420, kPpv = 0x428;
constexpr std::uint32_t kWidth = 0x100, kHeight = 0x104;
}  // namespace fake_genicam_reg

}  // namespace hg::sim
