// A method's input (methods/method.h) for a synthetic scene, as the harness builds it for a trial:
// an oracle source of the scene, its frames, and prerequisites resolved to each type's defaults.
#pragma once

#include <gtest/gtest.h>

#include <memory>
#include <string>

#include "methods/registry.h"
#include "sim/measurements.h"
#include "sim/scene.h"

namespace calibench {

struct SyntheticTrial {
  SceneTruth scene;
  std::unique_ptr<OracleSource> source;
  TrialCache cache;
  MethodInput input;

  // nullptr (after a test failure) when the source cannot be built.
  static std::unique_ptr<SyntheticTrial> Create(const SceneTruth& scene,
                                                const OracleOptions& options, uint64_t seed,
                                                std::vector<BoardLayout> boards = {}) {
    auto trial = std::unique_ptr<SyntheticTrial>(new SyntheticTrial);
    trial->scene = scene;
    std::string why;
    trial->source = OracleSource::Create(trial->scene, options, seed, &why);
    if (!trial->source) {
      ADD_FAILURE() << why;
      return nullptr;
    }
    SyntheticTrial* t = trial.get();
    t->input.source = t->source.get();
    t->input.image_width = 640;
    t->input.image_height = 480;
    t->input.boards = std::move(boards);
    t->input.parent_from_points = [t](double time) { return t->scene.ParentFromPoints(time); };
    t->input.cache = &t->cache;
    t->input.prerequisite = [t](const std::string& type,
                                const MethodInput& on) -> const MethodResult& {
      return t->cache.Get<MethodResult>("prerequisite " + type + on.WindowKey(), [&] {
        return FindMethodType(type)->create()->Run(on, nullptr);
      });
    };
    return trial;
  }

 private:
  SyntheticTrial() = default;
};

// A registered type's method with default options.
inline std::unique_ptr<Method> MakeMethod(const std::string& type) {
  const MethodType* t = FindMethodType(type);
  EXPECT_NE(t, nullptr) << type;
  return t ? t->create() : nullptr;
}

}  // namespace calibench
