// The `openni2` source's registration (camera_bridge/source_registry.hpp): its parameters, section openni2.
#include "camera_bridge/openni2/openni2_source.hpp"
#include "camera_bridge/source_registry.hpp"

namespace hg::camera_bridge {

SourceEntry openni2_source() {
  return {"openni2",
          "an OpenNI2 device (the first found, one named by URI, our virtual device hg-virtual://...) or an .oni "
          "recording (docs/openni2.md)",
          {{"uri", "", "device URI, hg-virtual://..., or an .oni file; empty: first device"},
           {"playback-speed", "1", ".oni: 1 = recorded rate; <= 0 frame by frame", false, runtime::ParamType::Number},
           {"loop", "", ".oni: start again after the last frame", true},
           {"ir", "true",
            "read the device's IR stream, when it has one, as the intensity image that tells dropout on steel from a "
            "hole (docs/openni2.md)",
            false, runtime::ParamType::Flag}},
          [](const SourceContext& c) {
            OpenNI2Options o;
            o.uri = c.text("uri");
            o.playback_speed = c.number("playback-speed");
            o.loop = c.flag("loop");
            o.ir = c.flag("ir");
            return make_openni2_source(o);
          },
          ""};
}

}  // namespace hg::camera_bridge
