// YamlMap: each key named once, in its read; a key no read takes is refused (file, line, the key,
// the keys taken) before any read runs; absent keys are read only by always().
#include <gtest/gtest.h>

#include "s3m/core/error.hpp"
#include "s3m/core/yaml_util.hpp"

namespace s3m {
namespace {

struct Pose {
  std::vector<double> t{0, 0, 0};
  std::string name = "none";
  bool required_seen = false;
  std::vector<std::string> order;
};

YamlMap pose_map(const YAML::Node& node, Pose& p) {
  YamlMap m(node, "p.yaml");
  m.get("t", p.t);
  m.on("name", [&p](const YAML::Node& v, const std::string& key) {
    p.name = v.as<std::string>();
    p.order.push_back(key);
  });
  m.always("frame", [&p](const YAML::Node& v, const std::string& key) {
    p.required_seen = !!v;
    p.order.push_back(key);
  });
  m.ignore("note");
  return m;
}

std::string error_of(const std::string& yaml) {
  Pose p;
  try {
    pose_map(YAML::Load(yaml), p).read();
  } catch (const ParseError& e) {
    EXPECT_TRUE(p.order.empty()) << "a read ran before the unknown key was refused";
    return e.what();
  }
  return "";
}

}  // namespace

TEST(YamlMap, ReadsTheKeysGivenInOrderAndAlwaysReadsAbsentOnes) {
  Pose p;
  pose_map(YAML::Load("name: a\nt: [1, 2, 3]\nnote: for people\n"), p).read();
  EXPECT_EQ(p.t, (std::vector<double>{1, 2, 3}));
  EXPECT_EQ(p.name, "a");
  EXPECT_FALSE(p.required_seen);
  EXPECT_EQ(p.order, (std::vector<std::string>{"name", "frame"}));  // declared order, not the file's
  Pose q;
  pose_map(YAML::Load("frame: 1\n"), q).read();
  EXPECT_TRUE(q.required_seen);
  EXPECT_EQ(q.name, "none");  // absent: kept
  Pose empty;
  pose_map(YAML::Load("~"), empty).read();  // an empty section is a map without keys
  EXPECT_EQ(empty.order, std::vector<std::string>{"frame"});
}

TEST(YamlMap, AnUnknownKeyIsNamedWithTheKeysTakenBeforeAnyRead) {
  // 'fram' is refused as a misspelling, not reported as 'frame' missing.
  EXPECT_NE(error_of("name: a\nfram: 1\n")
                .find("p.yaml:2: unknown key 'fram' (expected one of: t, name, frame, note)"),
            std::string::npos);
  EXPECT_NE(error_of("3\n").find("a value ('3') where a section is expected"), std::string::npos);
  EXPECT_NE(error_of("[1, 2]\n").find("a list where a section is expected"), std::string::npos);
  EXPECT_NE(error_of("? [a, b]\n: 1\n").find("a key that is not a plain name"), std::string::npos);
  Pose p;
  try {
    pose_map(YAML::Load("t: [1, x]\n"), p).read();
    FAIL() << "no error";
  } catch (const ParseError& e) {
    EXPECT_NE(std::string(e.what()).find("p.yaml:1: bad value for 't'"), std::string::npos) << e.what();
  }
}

}  // namespace s3m
