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

class Reader final : public FieldVisitor {
 public:
  Reader(const YAML::Node& node, const std::string& ctx, const std::set<std::string>& keep,
         std::string prefix, ReadKeys& out)
      : node_(node), ctx_(ctx), keep_(keep), prefix_(std::move(prefix)), out_(out) {}

 protected:
  void value(const char* key, ValueRef v) override {
    if (take(key)) std::visit([&](auto* member) { read_value(key, *member); }, v);
  }
  void custom(const char* key, const Custom& c) override {
    if (take(key)) c.read(node_[key], key, ctx_);
  }
  void section(const char* key, const Table& t) override {
    if (const YAML::Node sub = node_[key]) read_section(sub, t, ctx_, keep_, prefix_ + key + ".", out_);
  }

 private:
  template <class T>
  void read_value(const char* key, T& member) {
    member = yaml_as<T>(node_[key], key, ctx_);
  }

  // Whether to read key: present in the YAML and not to be kept.
  bool take(const char* key) {
    if (!node_[key]) return false;
    std::string path = prefix_ + key;
    const bool keep = keep_.count(path) > 0;
    (keep ? out_.kept : out_.set).push_back(std::move(path));
    return !keep;
  }

  const YAML::Node& node_;
  const std::string& ctx_;
  const std::set<std::string>& keep_;
  std::string prefix_;
  ReadKeys& out_;
};

void read_section(const YAML::Node& node, const Table& table, const std::string& ctx,
                  const std::set<std::string>& keep, const std::string& prefix, ReadKeys& out) {
  check_known_keys(node, keys(table), ctx);  // first, so that a typo is named with the keys taken
  Reader r(node, ctx, keep, prefix, out);
  table(r);
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
