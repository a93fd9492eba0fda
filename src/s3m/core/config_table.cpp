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

class Reader final : public FieldVisitor {
 public:
  Reader(const YAML::Node& node, const std::string& ctx, const std::set<std::string>& keep,
         std::string prefix, ReadKeys& out)
      : node_(node), ctx_(ctx), keep_(keep), prefix_(std::move(prefix)), out_(out) {}

 protected:
  void value(const char* key, ValueRef v) override {
    if (take(key))
      std::visit(
          [&](auto* member) { *member = yaml_as<std::decay_t<decltype(*member)>>(node_[key], key, ctx_); },
          v);
  }
  void custom(const char* key, const Custom& c) override {
    if (take(key)) c.read(node_[key], key, ctx_);
  }
  void section(const char* key, const Table& t) override {
    if (const YAML::Node sub = node_[key]) read(sub, t, ctx_, keep_, prefix_ + key + ".", out_);
  }

 public:
  static void read(const YAML::Node& node, const Table& table, const std::string& ctx,
                   const std::set<std::string>& keep, const std::string& prefix, ReadKeys& out) {
    check_known_keys(node, keys(table), ctx);
    Reader r(node, ctx, keep, prefix, out);
    table(r);
  }

 private:
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

std::string text_of(ValueRef v) {
  struct {
    std::string operator()(bool* b) const { return *b ? "true" : "false"; }
    std::string operator()(int* i) const { return std::to_string(*i); }
    std::string operator()(double* d) const { return format_number(*d); }
    std::string operator()(std::uint64_t* u) const { return std::to_string(*u); }
    std::string operator()(std::string* s) const { return *s; }
    std::string operator()(std::vector<std::string>*) const { return ""; }  // not a scalar: see node_of
  } text;
  return std::visit(text, v);
}

YAML::Node node_of(ValueRef v) {
  if (auto* const* list = std::get_if<std::vector<std::string>*>(&v)) {
    YAML::Node seq(YAML::NodeType::Sequence);
    for (const auto& s : **list) seq.push_back(s);
    seq.SetStyle(YAML::EmitterStyle::Flow);
    return seq;
  }
  return YAML::Node(text_of(v));
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
  Reader::read(node, table, ctx, keep, prefix, out);
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
