// config::read / write / keys / values over one table: absent keys keep their values, unknown keys
// are refused, kept keys are left alone, and what is written reads back as the same values.
#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include "s3m/core/config_table.hpp"
#include "s3m/core/error.hpp"

namespace s3m::config_test {

enum class Mode { kFast, kExact };

struct Inner {
  double range_m = 4.0;
  std::vector<std::string> names{"a", "b"};
};

struct Outer {
  int count = 3;
  bool on = true;
  std::string label;
  std::uint64_t seed = 1;
  Mode mode = Mode::kFast;
  Inner inner;
  double flat = 0.5;  // a member of a member filled from a flat key would look the same
};

void fields(config::FieldVisitor& v, Inner& c) {
  v("range_m", c.range_m);
  v("names", c.names);
}

void fields(config::FieldVisitor& v, Outer& c) {
  v("count", c.count);
  v("on", c.on);
  v("label", c.label);
  v("seed", c.seed);
  v("mode", config::choice(c.mode, {{"fast", Mode::kFast}, {"exact", Mode::kExact}, {"slow", Mode::kExact}}));
  v("inner", c.inner);
  v("flat_range_m", c.flat);
}

std::string error_of(const std::string& yaml) {
  Outer o;
  try {
    config::read(YAML::Load(yaml), config::table_of(o), "t.yaml");
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

TEST(ConfigTable, ReadsPresentKeysAndKeepsTheRest) {
  Outer o;
  const auto r =
      config::read(YAML::Load("count: 5\nmode: slow\ninner: {names: [x]}\n"), config::table_of(o), "t.yaml");
  EXPECT_EQ(o.count, 5);
  EXPECT_EQ(o.mode, Mode::kExact);
  EXPECT_EQ(o.inner.names, std::vector<std::string>{"x"});
  EXPECT_DOUBLE_EQ(o.inner.range_m, 4.0);
  EXPECT_TRUE(o.on);
  EXPECT_EQ(r.set, (std::vector<std::string>{"count", "mode", "inner.names"}));
  EXPECT_TRUE(r.kept.empty());
}

TEST(ConfigTable, KeysInKeepAreLeftAlone) {
  Outer o;
  const auto r = config::read(YAML::Load("count: 5\ninner: {range_m: 2}\n"), config::table_of(o), "t.yaml",
                              {"inner.range_m"});
  EXPECT_EQ(o.count, 5);
  EXPECT_DOUBLE_EQ(o.inner.range_m, 4.0);
  EXPECT_EQ(r.kept, std::vector<std::string>{"inner.range_m"});
}

TEST(ConfigTable, ErrorsNameFileLineKeyAndTheKeysTaken) {
  std::string e = error_of("count: 5\ninner: {rang_m: 2}\n");
  EXPECT_NE(e.find("t.yaml:2: unknown key 'rang_m' (expected one of: range_m, names)"), std::string::npos)
      << e;
  e = error_of("count: many\n");
  EXPECT_NE(e.find("t.yaml:1: bad value for 'count'"), std::string::npos) << e;
  e = error_of("mode: quick\n");
  EXPECT_NE(e.find("bad value 'quick' for 'mode' (expected fast | exact | slow)"), std::string::npos) << e;
  e = error_of("inner: 3\n");
  EXPECT_NE(e.find("a value ('3') where a section is expected"), std::string::npos) << e;
}

TEST(ConfigTable, WhatIsWrittenReadsBackAsTheSameValues) {
  Outer o;
  o.count = -7;
  o.on = false;
  o.label = "";
  o.seed = std::numeric_limits<std::uint64_t>::max();
  o.mode = Mode::kExact;
  o.inner.range_m = 0.1 + 0.2;  // not a short decimal
  o.inner.names = {"a b", "true", "1"};
  o.flat = std::numeric_limits<double>::infinity();
  const std::string text = config::to_text(config::write(o));
  EXPECT_NE(text.find("mode: exact"), std::string::npos) << text;  // the first name of the value
  Outer back;
  back.label = "x";
  config::read(YAML::Load(text), config::table_of(back), "t.yaml");
  EXPECT_EQ(config::values(back), config::values(o)) << text;
  EXPECT_EQ(back.inner.range_m, 0.1 + 0.2);
  EXPECT_EQ(back.label, "");
  EXPECT_TRUE(std::isinf(back.flat));
  EXPECT_EQ(config::keys(config::table_of(o)),
            (std::vector<std::string>{"count", "on", "label", "seed", "mode", "inner", "flat_range_m"}));
}

TEST(ConfigTable, NumbersAreWrittenShortAndExact) {
  EXPECT_EQ(config::format_number(0.02), "0.02");
  EXPECT_EQ(config::format_number(4.0), "4");
  EXPECT_EQ(config::format_number(1e-6), "1e-06");
  EXPECT_EQ(config::format_number(-std::numeric_limits<double>::infinity()), "-.inf");
}

}  // namespace s3m::config_test
