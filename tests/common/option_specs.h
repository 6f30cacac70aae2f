// The option declarations (OptionSpec: key, unit, doc) of a method, in VisitOptions order, for
// tests that check every option of every registered type.
#pragma once

#include <string>
#include <vector>

#include "methods/method.h"

namespace calibench {

inline std::vector<OptionSpec> OptionSpecs(const Method& method) {
  class Collector final : public OptionVisitor {
   public:
    std::vector<OptionSpec> specs;
    void Field(const OptionSpec& o, double*) override { specs.push_back(o); }
    void Field(const OptionSpec& o, int*) override { specs.push_back(o); }
    void Field(const OptionSpec& o, long*) override { specs.push_back(o); }
    void Field(const OptionSpec& o, bool*) override { specs.push_back(o); }
    void Field(const OptionSpec& o, std::string*, const std::vector<std::string>&) override {
      specs.push_back(o);
    }
    void Field(const OptionSpec& o, LensModel*) override { specs.push_back(o); }
    void Field(const OptionSpec& o, CameraSpec*) override { specs.push_back(o); }
    void FieldOrAll(const OptionSpec& o, double*) override { specs.push_back(o); }
  };
  Collector collector;
  VisitOptionsReadOnly(method, &collector);
  return collector.specs;
}

}  // namespace calibench
