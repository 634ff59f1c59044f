// The `genicam` source's registration (camera_bridge/source_registry.hpp): its parameters, section genicam.
#include "camera_bridge/genicam/genicam_source.hpp"
#include "camera_bridge/source_registry.hpp"

namespace hg::camera_bridge {

SourceEntry genicam_source() {
  return {"genicam",
          "a GigE Vision / USB3 Vision 3-D camera through Aravis (Coord3D_C16 range images or Coord3D_ABC32f "
          "organized clouds, Scan3d scale/offset/focal length/principal point; software trigger per job with "
          "--trigger job, else free-running; incomplete frames counted as dropped; docs/cameras.md)",
          {{"device", "",
            "Aravis device id (Vendor-Model-Serial, serial or IP address); empty: the first 3-D camera found"},
           runtime::text_param("format", "c16",
                               "c16 (Coord3D_C16 range image) | abc32f (Coord3D_ABC32f organized cloud, Z kept)",
                               {"c16", "abc32f"})},
          [](const SourceContext& c) {
            GenicamOptions o;
            o.device_id = c.text("device");
            o.software_trigger = c.job_trigger;
            o.format = c.text("format") == "c16" ? GenicamFormat::c16 : GenicamFormat::abc32f;
            return std::make_unique<GenicamSource>(o);
          },
          ""};
}

}  // namespace hg::camera_bridge
