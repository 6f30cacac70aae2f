// The one list of method types. Adding a method (README "Adding a method"): its source file in
// methods/ (a Method subclass and its Make...Method factory), one line here, its test in
// tests/methods/.
#include "methods/registry.h"

#include <algorithm>
#include <stdexcept>

#include "methods/options.h"

namespace calibench {

// Factories, one per type, defined in that type's source file.
std::unique_ptr<Method> MakeAdaptiveMethod();
std::unique_ptr<Method> MakeDltMethod();
std::unique_ptr<Method> MakeZhangMethod();
std::unique_ptr<Method> MakeZhangHandEyeMethod();
std::unique_ptr<Method> MakeCeresMethod();
std::unique_ptr<Method> MakeEkfMethod();
std::unique_ptr<Method> MakeEkfRigMethod();

const char* ToString(MethodFamily family) {
  switch (family) {
    case MethodFamily::kAdaptive:
      return "adaptive";
    case MethodFamily::kBatch:
      return "batch";
    case MethodFamily::kFilter:
      return "filter";
  }
  return "batch";
}

const std::vector<MethodType>& MethodTypes() {
  static const std::vector<MethodType> types = {
      {"adaptive",
       "the thesis's adaptive (Lyapunov) estimator on the source itself",
       MethodFamily::kAdaptive,
       true,
       {},
       MakeAdaptiveMethod},
      {"dlt",
       "normalised DLT of M on all frames pooled (non-coplanar points)",
       MethodFamily::kBatch,
       false,
       {},
       MakeDltMethod},
      {"zhang",
       "cv::calibrateCamera on the (frame, board) views; extrinsic by chordal rotation averaging",
       MethodFamily::kBatch,
       false,
       {"zhang_handeye"},
       MakeZhangMethod},
      {"zhang_handeye",
       "zhang's intrinsics; extrinsic by hand-eye calibration on board 0 (rotation from the "
       "quaternion form of AX = XB, translation as Tsai-Lenz)",
       MethodFamily::kBatch,
       false,
       {},
       MakeZhangHandEyeMethod},
      {"ceres",
       "maximum likelihood (Ceres) over the intrinsics and the constant extrinsic",
       MethodFamily::kBatch,
       false,
       {},
       MakeCeresMethod},
      {"ekf",
       "an extended Kalman filter on the intrinsics and the extrinsic, random-walk process",
       MethodFamily::kFilter,
       false,
       {},
       MakeEkfMethod},
      {"ekf_rig",
       "rig scenarios: one extended Kalman filter on every camera's intrinsics, camera 0's "
       "extrinsic and each camera's pose relative to camera 0, on all cameras' corners at once",
       MethodFamily::kFilter,
       false,
       {},
       MakeEkfRigMethod},
  };
  return types;
}

const MethodType* FindMethodType(const std::string& name) {
  for (const MethodType& t : MethodTypes()) {
    if (t.name == name) return &t;
  }
  return nullptr;
}

std::string MethodTypeNames() {
  std::string names;
  for (const MethodType& t : MethodTypes()) names += (names.empty() ? "" : ", ") + t.name;
  return names;
}

const std::vector<OutputSpec>& DeclaredOutputs() {
  static const std::vector<OutputSpec> outputs = [] {
    std::vector<OutputSpec> out;
    for (const MethodType& t : MethodTypes()) {
      for (const OutputSpec& o : t.create()->Outputs()) {
        const auto same = std::find_if(out.begin(), out.end(), [&](const OutputSpec& d) {
          return std::string(d.name) == o.name;
        });
        if (same == out.end()) {
          out.push_back(o);
        } else if (std::string(same->unit) != o.unit || std::string(same->label) != o.label ||
                   std::string(same->doc) != o.doc || same->summary != o.summary) {
          throw std::logic_error("method output " + std::string(o.name) +
                                 " is declared differently by " + t.name);
        }
      }
    }
    return out;
  }();
  return outputs;
}

bool CheckOutputs(const Method& method, const MethodResult& result, std::string* why) {
  const std::vector<OutputSpec> declared = method.Outputs();
  for (const auto& output : result.outputs) {
    const std::string& name = output.first;  // Not a structured binding: the lambda captures it.
    const bool known = std::any_of(declared.begin(), declared.end(),
                                   [&](const OutputSpec& o) { return name == o.name; });
    if (!known) {
      if (why) *why = "the method set output " + name + ", which its type does not declare";
      return false;
    }
  }
  return true;
}

MethodInstance& MethodInstance::operator=(const MethodInstance& other) {
  if (this == &other) return *this;
  name = other.name;
  type = other.type;
  enabled = other.enabled;
  convergence_tol = other.convergence_tol;
  method = other.method ? other.method->Clone() : nullptr;
  return *this;
}

MethodInstance MethodInstance::OfType(const std::string& type, const std::string& name) {
  MethodInstance instance;
  instance.name = name;
  instance.type = type;
  const MethodType* t = FindMethodType(type);
  if (t != nullptr) {
    instance.enabled = t->enabled_by_default;
    instance.method = t->create();
  }
  return instance;
}

bool operator==(const MethodInstance& a, const MethodInstance& b) {
  if (a.name != b.name || a.type != b.type || a.enabled != b.enabled ||
      a.convergence_tol != b.convergence_tol || !a.method != !b.method) {
    return false;
  }
  return !a.method || OptionsKey(*a.method) == OptionsKey(*b.method);
}

}  // namespace calibench
