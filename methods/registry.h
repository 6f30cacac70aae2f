// The registry of method types, and the named instances a scenario holds.
//
// Every type is listed once in registry.cc, in the order the map form of `methods:` gives its rows
// (adaptive, dlt, zhang, zhang_handeye, ceres, ...). A scenario's instances (config_io.h):
//   methods: [{name: adaptive-a100, type: adaptive, alpha: 100}, {name: ceres, type: ceres}]
// or the map form, one instance per type with name = type:
//   methods: {adaptive: {alpha: 100}, ceres: {enabled: true}}
// Keys every instance takes besides its type's options: name, type (list form), enabled and
// convergence_tol (the tolerance of converge_time_s on ||theta~|| for methods that report
// estimates over time).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "methods/method.h"

namespace calibench {

// What kind of estimator a type is: the report compares the adaptive estimator with the best
// batch method in every answer (schema.json's "family").
enum class MethodFamily {
  kAdaptive,  // The thesis's continuous-time estimator and its variants.
  kBatch,     // A solve on a set of frames (static, or repeated on windows online).
  kFilter,    // A recursive Bayesian filter (EKF).
};
const char* ToString(MethodFamily family);

struct MethodType {
  std::string name;         // As configs spell it.
  std::string description;  // One line.
  MethodFamily family = MethodFamily::kBatch;
  bool enabled_by_default = false;  // In the map form.
  // Map form only: types whose instance the entry of this type adds too, with the same options
  // (zhang adds zhang_handeye: one calibrateCamera, two extrinsic estimates).
  std::vector<std::string> companions;
  std::function<std::unique_ptr<Method>()> create;
};

// Every type, in registry order.
const std::vector<MethodType>& MethodTypes();
const MethodType* FindMethodType(const std::string& name);
// "adaptive, dlt, ..." for messages.
std::string MethodTypeNames();

// The outputs the registered types declare (Method::Outputs), in registry order, each name once:
// the method output columns of runs.csv (bench/run/run_row.h). Types that declare the same name
// declare it alike (a logic_error otherwise: a programmer error).
const std::vector<OutputSpec>& DeclaredOutputs();
// True when `result` sets only outputs that `method` declares; else false, *why naming the first
// other one.
bool CheckOutputs(const Method& method, const MethodResult& result, std::string* why);

// A named instance of a type with its options. Copies deep-copy the method.
struct MethodInstance {
  std::string name;
  std::string type;
  bool enabled = true;
  double convergence_tol = 1e-4;
  std::unique_ptr<Method> method;

  MethodInstance() = default;
  MethodInstance(const MethodInstance& other) { *this = other; }
  MethodInstance& operator=(const MethodInstance& other);
  MethodInstance(MethodInstance&&) = default;
  MethodInstance& operator=(MethodInstance&&) = default;

  // An instance of `type` named `name` with the type's default options (null method if the type
  // is unknown).
  static MethodInstance OfType(const std::string& type, const std::string& name);
};
bool operator==(const MethodInstance& a, const MethodInstance& b);

}  // namespace calibench
