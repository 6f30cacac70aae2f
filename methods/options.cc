#include "methods/options.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <memory>
#include <set>
#include <sstream>

#include "util/format.h"

namespace calibench {
namespace {

std::string Exact(double v) { return FormatNumber(v, 17); }

// Appends key=value for every option.
class KeyWriter final : public OptionVisitor {
 public:
  void Field(const OptionSpec& spec, double* v) override { Add(spec.key, Exact(*v)); }
  void Field(const OptionSpec& spec, int* v) override { Add(spec.key, std::to_string(*v)); }
  void Field(const OptionSpec& spec, long* v) override { Add(spec.key, std::to_string(*v)); }
  void Field(const OptionSpec& spec, bool* v) override { Add(spec.key, *v ? "true" : "false"); }
  void Field(const OptionSpec& spec, std::string* v, const std::vector<std::string>&) override {
    Add(spec.key, *v);
  }
  void Field(const OptionSpec& spec, LensModel* v) override { Add(spec.key, ToString(*v)); }
  void FieldOrAll(const OptionSpec& spec, double* v) override {
    Add(spec.key, std::isinf(*v) ? "all" : Exact(*v));
  }
  void Field(const OptionSpec& spec, CameraSpec* c) override {
    std::string camera;
    for (double p : c->intrinsics.Params()) camera += Exact(p) + " ";
    for (int i = 0; i < 9; ++i) camera += Exact(c->r_c(i / 3, i % 3)) + " ";
    for (int i = 0; i < 3; ++i) camera += Exact(c->x_c[i]) + " ";
    Add(spec.key, camera + (c->allow_improper_rotation ? "improper" : "proper"));
  }
  std::string text;

 private:
  void Add(const char* key, const std::string& value) {
    text += std::string(key) + "=" + value + ";";
  }
};

// Sets the one option named `key` from text.
class TextSetter final : public OptionVisitor {
 public:
  TextSetter(std::string key, std::string value) : key_(std::move(key)), value_(std::move(value)) {}
  void Field(const OptionSpec& spec, double* v) override {
    if (!Mine(spec.key)) return;
    char* end = nullptr;
    const double parsed = std::strtod(value_.c_str(), &end);
    if (value_.empty() || *end != '\0') return Fail("expected a number");
    *v = parsed;
  }
  void Field(const OptionSpec& spec, int* v) override {
    long parsed = 0;
    if (Mine(spec.key) && Integer(&parsed)) *v = static_cast<int>(parsed);
  }
  void Field(const OptionSpec& spec, long* v) override {
    long parsed = 0;
    if (Mine(spec.key) && Integer(&parsed)) *v = parsed;
  }
  void Field(const OptionSpec& spec, bool* v) override {
    if (!Mine(spec.key)) return;
    if (value_ == "true" || value_ == "false") {
      *v = value_ == "true";
    } else {
      Fail("expected true or false");
    }
  }
  void Field(const OptionSpec& spec, std::string* v,
             const std::vector<std::string>& choices) override {
    if (!Mine(spec.key)) return;
    if (!choices.empty() && std::find(choices.begin(), choices.end(), value_) == choices.end()) {
      return Fail("not one of the allowed values");
    }
    *v = value_;
  }
  void Field(const OptionSpec& spec, LensModel* v) override {
    if (Mine(spec.key) && !ParseLensModel(value_, v)) Fail("not a lens model");
  }
  void Field(const OptionSpec& spec, CameraSpec*) override {
    if (Mine(spec.key)) Fail("a camera cannot be set from text");
  }
  void FieldOrAll(const OptionSpec& spec, double* v) override {
    if (!Mine(spec.key)) return;
    if (value_ == "all") {
      *v = std::numeric_limits<double>::infinity();
      return;
    }
    char* end = nullptr;
    const double parsed = std::strtod(value_.c_str(), &end);
    if (value_.empty() || *end != '\0') return Fail("expected a number of seconds or all");
    *v = parsed;
  }
  bool found = false;
  std::string error;

 private:
  bool Mine(const char* key) {
    if (key_ != key) return false;
    found = true;
    return true;
  }
  bool Integer(long* out) {
    char* end = nullptr;
    *out = std::strtol(value_.c_str(), &end, 10);
    if (value_.empty() || *end != '\0') {
      Fail("expected an integer");
      return false;
    }
    if (*out < std::numeric_limits<int>::min() || *out > std::numeric_limits<int>::max()) {
      Fail("out of range");
      return false;
    }
    return true;
  }
  void Fail(const std::string& reason) { error = key_ + ": '" + value_ + "': " + reason; }
  std::string key_, value_;
};

}  // namespace

std::string OptionsKey(const Method& method) {
  KeyWriter writer;
  VisitOptionsReadOnly(method, &writer);
  return writer.text;
}

bool SetOption(Method* method, const std::string& key, const std::string& value, std::string* why) {
  const std::unique_ptr<Method> trial = method->Clone();  // *method changes only on success.
  TextSetter setter(key, value);
  trial->VisitOptions(&setter);
  std::string reason = setter.error;
  if (!setter.found) reason = "unknown option '" + key + "'";
  if (reason.empty() && !trial->Check(&reason)) reason = key + ": " + reason;
  if (!reason.empty()) {
    if (why) *why = reason;
    return false;
  }
  TextSetter apply(key, value);
  method->VisitOptions(&apply);
  return true;
}

}  // namespace calibench
