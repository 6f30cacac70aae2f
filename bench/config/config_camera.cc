// The camera of a scenario's YAML (truth and the methods' `camera` options): intrinsics with
// their lens family, R_C, x_C (config_parsers.h). Split from config_io.cc, which reads the rest.
#include <yaml-cpp/yaml.h>

#include <string>
#include <vector>

#include "bench/config/config_parsers.h"
#include "bench/config/yaml_reader.h"

namespace calibench {
namespace {

using config_internal::Reader;

void ParseIntrinsics(const Reader& r, const YAML::Node& node, const std::string& field,
                     CameraIntrinsics* k) {
  if (node.IsMap() && node["k5"]) {
    r.Fail(node["k5"], Reader::Join(field, "k5"),
           "no lens model has k5: the equidistant (fisheye, Kannala-Brandt) model has k1..k4, as "
           "OpenCV's cv::fisheye and Kalibr's equidistant; radtan has k1 k2 p1 p2 k3");
  }
  r.CheckKeys(node, field,
              {"lens_family", "fku_px", "fkv_px", "phi_deg", "u0_px", "v0_px", "k1", "k2", "p1",
               "p2", "k3", "k4", "xi", "alpha", "beta"});
  if (node["lens_family"]) {
    const std::string family =
        r.Scalar<std::string>(node["lens_family"], Reader::Join(field, "lens_family"), "a string");
    constexpr LensFamily kFamilies[] = {LensFamily::kRadTan, LensFamily::kEquidistant,
                                        LensFamily::kUnified, LensFamily::kEucm,
                                        LensFamily::kDoubleSphere};
    bool known = false;
    for (LensFamily f : kFamilies) {
      if (family == ToString(f)) k->family = f, known = true;
    }
    if (!known) {
      r.Fail(node["lens_family"], Reader::Join(field, "lens_family"),
             "unknown lens family '" + family +
                 "' (radtan, equidistant, unified, eucm, double-sphere)");
    }
  }
  r.Set(node, "fku_px", field, &k->fku_px);
  r.Set(node, "fkv_px", field, &k->fkv_px);
  r.Set(node, "phi_deg", field, &k->phi_deg);
  r.Set(node, "u0_px", field, &k->u0_px);
  r.Set(node, "v0_px", field, &k->v0_px);
  r.Set(node, "k1", field, &k->k1);
  r.Set(node, "k2", field, &k->k2);
  r.Set(node, "p1", field, &k->p1);
  r.Set(node, "p2", field, &k->p2);
  r.Set(node, "k3", field, &k->k3);
  r.Set(node, "k4", field, &k->k4);
  r.Set(node, "xi", field, &k->xi);        // Unified, double-sphere.
  r.Set(node, "alpha", field, &k->alpha);  // Eucm, double-sphere.
  r.Set(node, "beta", field, &k->beta);    // Eucm.
  std::string why;
  if (!k->Check(&why)) r.Fail(node, field, why);
}

}  // namespace

namespace config_internal {
void ParseCamera(const Reader& r, const YAML::Node& node, const std::string& field, CameraSpec* c,
                 const std::vector<std::string>& extra_keys) {
  std::vector<std::string> keys = {"intrinsics", "R_C", "x_C", "allow_improper_rotation"};
  keys.insert(keys.end(), extra_keys.begin(), extra_keys.end());
  r.CheckKeys(node, field, keys);
  r.Set(node, "allow_improper_rotation", field, &c->allow_improper_rotation);
  r.If(node, "intrinsics", field,
       [&](auto n, auto f) { ParseIntrinsics(r, n, f, &c->intrinsics); });
  r.Set(node, "x_C", field, &c->x_c);
  r.If(node, "R_C", field, [&](auto n, auto f) { c->r_c = r.Matrix3(n, f); });
  // Checked on every file that sets or opts in, so an override can allow a base's matrix.
  if (node["R_C"].IsDefined() || node["allow_improper_rotation"].IsDefined()) {
    std::string why;
    const YAML::Node at = node["R_C"].IsDefined() ? node["R_C"] : node;
    if (!CheckRotation(c->r_c, 1e-9, c->allow_improper_rotation, &why)) {
      r.Fail(at, Reader::Join(field, "R_C"), why);
    }
  }
}
}  // namespace config_internal

}  // namespace calibench
