#include "s3m/core/config_table.hpp"

#include <charconv>
#include <cmath>

namespace s3m::config {
namespace {

// The table's own keys.
class KeyLister final : public FieldVisitor {
 public:
  std::vector<std::string> keys;

 protected:
  void value(const char* key, ValueRef) override { keys.emplace_back(key); }
  void custom(const char* key, const Custom&) override { keys.emplace_back(key); }
  void section(const char* key, const Table&) override { keys.emplace_back(key); }
};

void read_section(const YAML::Node& node, const Table& table, const std::string& ctx,
                  const std::set<std::string>& keep, const std::string& prefix, ReadKeys& out);

// Declares a read of each key of the table on one YamlMap.
class Reader final : public FieldVisitor {
 public:
  Reader(YamlMap& map, const std::string& ctx, const std::set<std::string>& keep, std::string prefix,
         ReadKeys& out)
      : map_(map), ctx_(ctx), keep_(keep), prefix_(std::move(prefix)), out_(out) {}

 protected:
  void value(const char* key, ValueRef v) override {
    map_.on(key, [this, v](const YAML::Node& value, const std::string& k) {
      if (take(k))
        std::visit([&](auto* member) { *member = yaml_as<std::decay_t<decltype(*member)>>(value, k, ctx_); },
                   v);
    });
  }
  void custom(const char* key, const Custom& c) override {
    map_.on(key, [this, read = c.read](const YAML::Node& value, const std::string& k) {
      if (take(k)) read(value, k, ctx_);
    });
  }
  void section(const char* key, const Table& t) override {
    map_.on(key, [this, t](const YAML::Node& sub, const std::string& k) {
      read_section(sub, t, ctx_, keep_, prefix_ + k + ".", out_);
    });
  }

 private:
  // Whether to read a key present in the YAML: not when it is to be kept.
  bool take(const std::string& key) {
    std::string path = prefix_ + key;
    const bool keep = keep_.count(path) > 0;
    (keep ? out_.kept : out_.set).push_back(std::move(path));
    return !keep;
  }

  YamlMap& map_;
  const std::string& ctx_;
  const std::set<std::string>& keep_;
  std::string prefix_;
  ReadKeys& out_;
};

void read_section(const YAML::Node& node, const Table& table, const std::string& ctx,
                  const std::set<std::string>& keep, const std::string& prefix, ReadKeys& out) {
  YamlMap map(node, ctx);
  Reader r(map, ctx, keep, prefix, out);
  table(r);
  map.read();  // a key the table does not take is refused before any is read
}

// A value as YAML: scalars as text (numbers the shortest that read back exactly), lists in flow style.
YAML::Node node_of(ValueRef v) {
  struct {
    YAML::Node operator()(bool* b) const { return YAML::Node(*b ? "true" : "false"); }
    YAML::Node operator()(int* i) const { return YAML::Node(std::to_string(*i)); }
    YAML::Node operator()(double* d) const { return YAML::Node(format_number(*d)); }
    YAML::Node operator()(std::uint64_t* u) const { return YAML::Node(std::to_string(*u)); }
    YAML::Node operator()(std::string* s) const { return YAML::Node(*s); }
    YAML::Node operator()(std::vector<std::string>* list) const {
      YAML::Node seq(YAML::NodeType::Sequence);
      for (const auto& s : *list) seq.push_back(s);
      seq.SetStyle(YAML::EmitterStyle::Flow);
      return seq;
    }
  } node;
  return std::visit(node, v);
}

class Writer final : public FieldVisitor {
 public:
  YAML::Node out{YAML::NodeType::Map};

 protected:
  void value(const char* key, ValueRef v) override { out[key] = node_of(v); }
  void custom(const char* key, const Custom& c) override { out[key] = c.write(); }
  void section(const char* key, const Table& t) override { out[key] = write(t); }
};

class ValueLister final : public FieldVisitor {
 public:
  explicit ValueLister(std::string prefix) : prefix_(std::move(prefix)) {}
  std::vector<std::pair<std::string, std::string>> values;

 protected:
  void value(const char* key, ValueRef v) override { add(key, node_of(v)); }
  void custom(const char* key, const Custom& c) override { add(key, c.write()); }
  void section(const char* key, const Table& t) override {
    ValueLister inner(prefix_ + key + ".");
    t(inner);
    values.insert(values.end(), inner.values.begin(), inner.values.end());
  }

 private:
  void add(const char* key, const YAML::Node& n) {
    YAML::Emitter e;
    e << YAML::Flow << n;
    values.emplace_back(prefix_ + key, e.c_str());
  }
  std::string prefix_;
};

}  // namespace

ReadKeys read(const YAML::Node& node, const Table& table, const std::string& ctx,
              const std::set<std::string>& keep, const std::string& prefix) {
  ReadKeys out;
  read_section(node, table, ctx, keep, prefix, out);
  return out;
}

YAML::Node write(const Table& table) {
  Writer w;
  table(w);
  return w.out;
}

std::vector<std::string> keys(const Table& table) {
  KeyLister k;
  table(k);
  return k.keys;
}

std::vector<std::pair<std::string, std::string>> values(const Table& table) {
  ValueLister v("");
  table(v);
  return v.values;
}

std::string to_text(const YAML::Node& node) {
  YAML::Emitter e;
  e.SetIndent(2);
  e << node;
  return std::string(e.c_str()) + "\n";
}

std::string format_number(double v) {
  if (std::isnan(v)) return ".nan";
  if (std::isinf(v)) return v > 0 ? ".inf" : "-.inf";
  char buf[32];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  return std::string(buf, r.ptr);
}

}  // namespace s3m::config
