#pragma once
// Config structs declare their YAML keys once, in a table: a function
//   void fields(config::FieldVisitor& v, FooConfig& c) { v("max_range_m", c.max_range_m); v("insert",
//   c.insert); }
// in the struct's namespace, naming each key with the member it fills. A member that has a table
// of its own is a nested section; a member of a member may fill a flat key
// (v("odometry_downsample", c.odometry.downsample)). Everything else is derived from that one
// table, so a key cannot be read but not written, or listed but not read: the reader (absent keys
// keep their values, unknown keys are refused with file and line), the writer of the values in
// effect (config_effective.yaml), and the dotted names of the keys a file wrote, which automatic
// decisions must leave alone (pipeline/config_overlays.hpp).
#include <cstdint>
#include <functional>
#include <set>
#include <string>
#include <type_traits>
#include <utility>
#include <variant>
#include <vector>

#include <yaml-cpp/yaml.h>

#include "s3m/core/error.hpp"
#include "s3m/core/yaml_util.hpp"

namespace s3m::config {

// The member types a key can fill directly.
using ValueRef = std::variant<bool*, int*, double*, std::uint64_t*, std::string*, std::vector<std::string>*>;

// A value with a YAML form of its own (an enum spelled as a name, a pose as {t, q}). read() gets
// the key's node (present); write() returns the node for the value in effect.
struct Custom {
  std::function<void(const YAML::Node& value, const std::string& key, const std::string& ctx)> read;
  std::function<YAML::Node()> write;
};

class FieldVisitor;
using Table = std::function<void(FieldVisitor&)>;  // a struct's fields() bound to one object

class FieldVisitor {
 public:
  virtual ~FieldVisitor() = default;
  void operator()(const char* key, const Custom& c) { custom(key, c); }
  template <class T>
  void operator()(const char* key, T& member) {
    if constexpr (std::is_same_v<std::remove_const_t<T>, Custom>)
      custom(key, member);
    else if constexpr (std::is_constructible_v<ValueRef, T*>)
      value(key, &member);
    else  // a nested section: its own table, found next to its struct
      section(key, [&member](FieldVisitor& v) { fields(v, member); });
  }

 protected:
  virtual void value(const char* key, ValueRef v) = 0;
  virtual void custom(const char* key, const Custom& c) = 0;
  virtual void section(const char* key, const Table& t) = 0;
};

template <class T>
Table table_of(T& c) {
  return [&c](FieldVisitor& v) { fields(v, c); };
}

// What a read did, as dotted key paths below `prefix`: the keys it set, and those present in the
// YAML that it left alone because `keep` named them.
struct ReadKeys {
  std::vector<std::string> set, kept;
};

// Reads a YAML map into the object behind `table`. Absent keys keep their values; an unknown key
// is a ParseError naming ctx, the line and the keys the section takes (YamlMap).
ReadKeys read(const YAML::Node& node, const Table& table, const std::string& ctx,
              const std::set<std::string>& keep = {}, const std::string& prefix = "");

// Every key of the table with its value, as a YAML map in table order.
YAML::Node write(const Table& table);
template <class T>
YAML::Node write(const T& c) {
  T copy = c;  // the table binds a mutable object; the writer only reads it
  return write(table_of(copy));
}

// The table's own keys, in order (those an unknown-key error lists).
std::vector<std::string> keys(const Table& table);
// Every key and its value as text, dotted ("features.orb.n_features"), in table order.
std::vector<std::pair<std::string, std::string>> values(const Table& table);
template <class T>
std::vector<std::pair<std::string, std::string>> values(const T& c) {
  T copy = c;
  return values(table_of(copy));
}

// A YAML document as block-style text (lists and small custom values in flow style).
std::string to_text(const YAML::Node& node);

// The shortest text that reads back as exactly v ("0.02", "1e-06", ".inf").
std::string format_number(double v);

// An enum spelled as one of `names` in YAML; the first name of a value is the one written, later
// ones are accepted spellings. A name not in the list is a ParseError listing them.
template <class E>
Custom choice(E& value, std::vector<std::pair<std::string, E>> names) {
  auto read = [&value, names](const YAML::Node& n, const std::string& key, const std::string& ctx) {
    const auto s = yaml_as<std::string>(n, key, ctx);
    std::string allowed;
    for (const auto& [name, v] : names) {
      if (name == s) {
        value = v;
        return;
      }
      allowed += (allowed.empty() ? "" : " | ") + name;
    }
    throw ParseError(ctx, n.Mark().line + 1, "bad value '" + s + "' for '" + key + "'", allowed);
  };
  auto write = [&value, names] {
    for (const auto& [name, v] : names)
      if (v == value) return YAML::Node(name);
    throw Error("config: value " + std::to_string(static_cast<int>(value)) + " has no name");
  };
  return {read, write};
}

}  // namespace s3m::config
