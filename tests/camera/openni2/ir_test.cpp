// The intensity image through OpenNI2: the virtual device's IR stream carries the renderer's intensity
// image of the same frame, the `openni2` source pairs it with its depth frame, and a realistic scan through
// OpenNI2 then gives the plate the renderer's truth has (one outer loop, the true cut-outs), as the
// synthetic source with its intensity image does. The expectations are the scene renderer called directly
// and the generator's polygons (tests/outline_service/realistic_scan.hpp).
#include <chrono>

#include "camera_bridge/openni2/openni2_source.hpp"
#include "openni2_test_util.hpp"
#include "tests/outline_service/realistic_scan.hpp"

namespace hg::camera_bridge {
namespace {

using namespace testing;
using namespace std::chrono_literals;

constexpr const char* kRealistic = "plate-hole-slot-realistic";

camera::DepthFrame grab_one(camera::DepthSource& source) {
  std::optional<camera::DepthFrame> f;
  for (int attempt = 0; attempt < 10 && !f; ++attempt) f = source.grab(5s);
  if (!f) throw std::runtime_error("no frame");
  return *f;
}

sim::RenderedFrame truth_of(const std::string& scene, std::int64_t seq) {
  return sim::render(sim::scene_preset(scene), sim::camera_profile("pm806"), static_cast<std::uint64_t>(seq));
}

// A full-scale 16-bit intensity image back on the renderer's 8-bit scale (255 = saturated).
cv::Mat to_8bit(const cv::Mat& intensity16) {
  cv::Mat out;
  intensity16.convertTo(out, CV_8UC1, 255.0 / 65535.0);
  return out;
}

TEST(OpenNI2VirtualIr, TheDeviceOffersAnIrStreamWhereTheSceneRendersIntensity) {
  init_openni_from_private_folder();
  openni::Device device;
  ASSERT_EQ(device.open((std::string("hg-virtual://") + kRealistic + "?profile=pm806").c_str()), openni::STATUS_OK);
  ASSERT_TRUE(device.hasSensor(openni::SENSOR_IR));
  openni::VideoStream ir;
  ASSERT_EQ(ir.create(device, openni::SENSOR_IR), openni::STATUS_OK);
  const sim::CameraProfile profile = sim::camera_profile("pm806");
  // GRAY16 with 10 significant bits by default, as PrimeSense and Orbbec devices send IR; GRAY8 offered.
  EXPECT_EQ(ir.getVideoMode().getPixelFormat(), openni::PIXEL_FORMAT_GRAY16);
  EXPECT_EQ(ir.getVideoMode().getResolutionX(), profile.width);
  EXPECT_EQ(ir.getVideoMode().getResolutionY(), profile.height);
  EXPECT_EQ(ir.getMaxPixelValue(), 1023);
  ASSERT_EQ(ir.start(), openni::STATUS_OK);
  openni::VideoFrameRef ref;
  ASSERT_EQ(ir.readFrame(&ref), openni::STATUS_OK);
  const cv::Mat want = truth_of(kRealistic, ref.getFrameIndex()).intensity;
  ASSERT_EQ(ref.getWidth(), want.cols);
  ASSERT_EQ(ref.getHeight(), want.rows);
  const cv::Mat got(ref.getHeight(), ref.getWidth(), CV_16UC1, const_cast<void*>(ref.getData()),
                    ref.getStrideInBytes());
  cv::Mat back;  // 10 bits back to 8: exact, the 10-bit step being a quarter of the 8-bit one
  got.convertTo(back, CV_8UC1, 255.0 / 1023.0);
  EXPECT_EQ(differing_pixels(back, want), 0);
  EXPECT_EQ(cv::countNonZero(got == 1023), cv::countNonZero(want == 255));  // saturated stays full scale
  EXPECT_GT(cv::countNonZero(want == 255), 0) << "the realistic preset has glints";
  ir.stop();
  ir.destroy();
  device.close();

  ASSERT_EQ(device.open("hg-virtual://plate-hole-slot?profile=pm806"), openni::STATUS_OK);
  EXPECT_FALSE(device.hasSensor(openni::SENSOR_IR)) << "a scene without an intensity image has no IR sensor";
  device.close();
}

TEST(OpenNI2VirtualIr, TheSourcePairsEachDepthFrameWithItsIntensityImage) {
  init_openni_from_private_folder();
  OpenNI2Options o;
  o.uri = std::string("hg-virtual://") + kRealistic + "?profile=pm806&fps=10";
  OpenNI2Source source(o);
  source.open();
  EXPECT_TRUE(source.reads_ir());
  for (int i = 0; i < 4; ++i) {
    const camera::DepthFrame f = grab_one(source);
    const sim::RenderedFrame t = truth_of(kRealistic, f.seq);
    EXPECT_EQ(differing_pixels(f.depth, t.depth), 0) << "frame " << f.seq;
    ASSERT_EQ(f.intensity.type(), CV_16UC1) << "frame " << f.seq;
    EXPECT_EQ(differing_pixels(to_8bit(f.intensity), t.intensity), 0) << "frame " << f.seq << ": not its own";
    EXPECT_EQ(cv::countNonZero(f.intensity == 65535), cv::countNonZero(t.intensity == 255));
  }
}

TEST(OpenNI2VirtualIr, WithoutIrTheDepthComesAlone) {
  init_openni_from_private_folder();
  for (const bool device_has_ir : {false, true}) {
    OpenNI2Options o;
    o.uri = device_has_ir ? std::string("hg-virtual://") + kRealistic + "?profile=pm806&fps=10"
                          : "hg-virtual://plate-hole-slot?profile=pm806&fps=10";
    o.ir = !device_has_ir;  // the IR stream turned off, or a device that has none
    const std::string scene = device_has_ir ? kRealistic : "plate-hole-slot";
    OpenNI2Source source(o);
    source.open();
    EXPECT_FALSE(source.reads_ir());
    for (int i = 0; i < 2; ++i) {
      const camera::DepthFrame f = grab_one(source);
      EXPECT_EQ(differing_pixels(f.depth, truth_of(scene, f.seq).depth), 0) << scene << " frame " << f.seq;
      EXPECT_TRUE(f.intensity.empty()) << scene;
    }
  }
}

// The realistic plate's glare band (saturated pixels without depth) splits it when depth is all there is;
// with the IR stream the scan through OpenNI2 is the truth's plate, as the synthetic source's is.
TEST(OpenNI2VirtualIr, ARealisticScanThroughOpenNI2IsTheTruthsPlate) {
  init_openni_from_private_folder();
  OpenNI2Options o;
  o.uri = std::string("hg-virtual://") + kRealistic + "?profile=pm806&fps=5";
  OpenNI2Source source(o);
  source.open();
  const camera::DepthFrame f = grab_one(source);
  const sim::RenderedFrame truth = truth_of(kRealistic, f.seq);
  sim::RenderedFrame through = truth;
  through.depth = f.depth;
  const test::Accuracy a =
      test::measure(test::scan(through, SegmentParams{}, test::shipped_rules(), f.intensity), truth);
  const test::Accuracy synthetic =
      test::measure(test::scan(truth, SegmentParams{}, test::shipped_rules(), truth.intensity), truth);
  ASSERT_TRUE(a.ok);
  EXPECT_EQ(a.outer, 1);
  EXPECT_EQ(a.holes_found, a.truth_holes);
  EXPECT_EQ(a.holes_extra, 0);
  EXPECT_EQ(a.holes, a.truth_holes);
  EXPECT_NEAR(a.part_area, a.truth_area, 0.01 * a.truth_area) << "the part's area";
  // The same plate as the synthetic source with its intensity image gives.
  EXPECT_EQ(a.outer, synthetic.outer);
  EXPECT_EQ(a.holes, synthetic.holes);
  EXPECT_NEAR(a.part_area, synthetic.part_area, 1e-3 * synthetic.part_area);
}

}  // namespace
}  // namespace hg::camera_bridge
