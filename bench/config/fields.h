// One declaration per configuration field: the YAML key, the member, its type, its default (the
// member's initializer), its unit, a one-line doc and its check. Each configuration struct has a
// Visit(FieldVisitor&, T&) (scenario_fields.cc) that lists its fields once; the parser, the writer,
// equality, the "did you mean" key lists, the sweepable keys and the reference documentation
// (`calibench config-reference`, docs/configuration.md) are visitors of it. No YAML here: the
// YAML visitors live in the config I/O files (config_fields_io.cc).
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "methods/registry.h"
#include "sim/scene.h"

namespace calibench {

struct PointsConfig;

enum FieldFlag : unsigned {
  kOmitUnset = 1u << 0,     // Not written when unset (NaN, empty, zero; an enum: its first name).
  kNotWritten = 1u << 1,    // Read only (how a value was written, e.g. a preset's name).
  kNotCompared = 1u << 2,   // Not part of equality (a preset's name: its values are compared).
  kNotSweepable = 1u << 3,  // Not a sweep axis (top-level scenario fields only).
  kRequired = 1u << 4,      // Readers refuse a mapping without it (items of a list).
};

struct FieldSpec {
  const char* key;
  const char* unit = "";  // "" when none.
  const char* doc = "";
  const char* constraint = "";  // The check in words, for the reference ("> 0").
  // The check of a number as read; *why gets the reason (the reader names file, line and field).
  bool (*check)(double value, std::string* why) = nullptr;
  unsigned flags = 0;
};

// A closed set's spelling in configs: choices[i] is the YAML name; `noun` words the error
// ("unknown lens family 'x'"; empty: "'x' is not one of: ...").
struct Choices {
  std::vector<std::string> names;
  const char* noun = "";
  bool first_is_unset = false;  // An enum: its first name is the default (kOmitUnset omits it).
};

// A nested mapping: `visit` lists its fields; `reset` (optional) makes a section that replaces the
// base's as a whole; `flow` writes it on one line; `written` false: the writer omits it.
struct SectionOps {
  std::function<void(class FieldVisitor&)> visit;
  std::function<void()> reset;
  bool flow = false;
  bool written = true;
};

// A list of mappings: its size, resize, and a visit of item i.
struct ListOps {
  size_t size = 0;
  std::function<void(size_t)> resize;
  std::function<void(size_t, class FieldVisitor&)> visit;
  bool flow_items = true;
  bool allow_empty = false;  // `[]` is a value (e.g. clears a base's list), not an error.
  // Readers call it with item i's place in its file ("file:line:col"), for checks made later.
  std::function<void(size_t, const std::string& where)> located;
};

class FieldVisitor {
 public:
  virtual ~FieldVisitor() = default;
  // True when the fields hold the values an absent key leaves (a reader, the reference).
  virtual bool Reads() const { return false; }
  virtual void Field(const FieldSpec& f, double* v) = 0;
  virtual void Field(const FieldSpec& f, int* v) = 0;
  virtual void Field(const FieldSpec& f, uint64_t* v) = 0;
  virtual void Field(const FieldSpec& f, bool* v) = 0;
  virtual void Field(const FieldSpec& f, std::string* v) = 0;
  virtual void Field(const FieldSpec& f, std::string* v, const Choices& choices) = 0;
  virtual void Field(const FieldSpec& f, Eigen::Vector3d* v) = 0;
  virtual void Field(const FieldSpec& f, Eigen::Matrix3d* v) = 0;
  virtual void Field(const FieldSpec& f, std::vector<Eigen::Vector3d>* v) = 0;  // [[x, y, z], ...]
  // [width, height]-like pairs of integers.
  virtual void Field(const FieldSpec& f, int* first, int* second) = 0;
  virtual void Section(const FieldSpec& f, const SectionOps& ops) = 0;
  virtual void List(const FieldSpec& f, const ListOps& ops) = 0;
  // Sections with their own grammar (config I/O reads and writes them by hand).
  virtual void Field(const FieldSpec& f, PointsConfig* v) = 0;
  virtual void Field(const FieldSpec& f, std::vector<MethodInstance>* v) = 0;
  // Readers run `ok` after the fields above it; false fails naming `key` (nullptr: the section).
  virtual void Check(const char* /*key*/, const std::function<bool(std::string*)>& /*ok*/) {}
  // `key` may not be given together with any of `others`.
  virtual void Exclusive(const char* /*key*/, const std::vector<const char*>& /*others*/,
                         const char* /*reason*/) {}
  // A key refused with its reason (a near miss worth explaining).
  virtual void Refused(const char* /*key*/, const char* /*reason*/) {}
};

// A visitor that sees only each field's declaration (its FieldSpec), whatever its type: key
// lists and other walks over the declarations derive from it and implement Spec().
class SpecVisitor : public FieldVisitor {
 public:
  virtual void Spec(const FieldSpec& f) = 0;
  void Field(const FieldSpec& f, double*) override { Spec(f); }
  void Field(const FieldSpec& f, int*) override { Spec(f); }
  void Field(const FieldSpec& f, uint64_t*) override { Spec(f); }
  void Field(const FieldSpec& f, bool*) override { Spec(f); }
  void Field(const FieldSpec& f, std::string*) override { Spec(f); }
  void Field(const FieldSpec& f, std::string*, const Choices&) override { Spec(f); }
  void Field(const FieldSpec& f, Eigen::Vector3d*) override { Spec(f); }
  void Field(const FieldSpec& f, Eigen::Matrix3d*) override { Spec(f); }
  void Field(const FieldSpec& f, std::vector<Eigen::Vector3d>*) override { Spec(f); }
  void Field(const FieldSpec& f, int*, int*) override { Spec(f); }
  void Section(const FieldSpec& f, const SectionOps&) override { Spec(f); }
  void List(const FieldSpec& f, const ListOps&) override { Spec(f); }
  void Field(const FieldSpec& f, PointsConfig*) override { Spec(f); }
  void Field(const FieldSpec& f, std::vector<MethodInstance>*) override { Spec(f); }
};

// An enum class through its name table (YAML spelling, in declaration order).
template <typename E>
struct EnumNames {
  std::vector<std::pair<E, const char*>> entries;
  const char* noun = "";
  const char* Name(E e) const {
    for (const auto& [value, name] : entries)
      if (value == e) return name;
    return entries.front().second;
  }
  bool Parse(const std::string& name, E* e) const {
    for (const auto& [value, n] : entries)
      if (name == n) return *e = value, true;
    return false;
  }
  Choices AsChoices() const {
    Choices c{{}, noun, true};
    for (const auto& entry : entries) c.names.push_back(entry.second);
    return c;
  }
};

template <typename E>
void VisitEnum(FieldVisitor& v, const FieldSpec& f, E* e, const EnumNames<E>& table) {
  std::string name = table.Name(*e);
  v.Field(f, &name, table.AsChoices());
  table.Parse(name, e);
}

// A nested struct with its own Visit.
template <typename T>
void VisitSection(FieldVisitor& v, const FieldSpec& f, T* section, bool flow = false,
                  bool written = true) {
  SectionOps ops;
  ops.visit = [section](FieldVisitor& w) { Visit(w, *section); };
  ops.flow = flow;
  ops.written = written;
  v.Section(f, ops);
}

template <typename T>
void VisitList(FieldVisitor& v, const FieldSpec& f, std::vector<T>* list) {
  ListOps ops;
  ops.size = list->size();
  ops.resize = [list](size_t n) { list->resize(n); };
  ops.visit = [list](size_t i, FieldVisitor& w) { Visit(w, (*list)[i]); };
  v.List(f, ops);
}

}  // namespace calibench
