#include "f2c/util/fields.h"

#include <gtest/gtest.h>

#include "f2c/util/fields_json.h"
#include "f2c/util/fields_set.h"

namespace f2c {
namespace {

enum class Shape { kRound, kSquare };
F2C_ENUM_NAMES(Shape, {{Shape::kRound, "round"}, {Shape::kSquare, "square"}})

struct Inner {
  double radius = 0.5;
  int calls_to_check = 0;
  template <class V>
  void Fields(V& v) {
    F2C_FIELD(v, radius, "--radius", Positive(), "a radius (m)");
  }
  void Check() const { CheckFields(*this); }
};

struct Outer {
  int count = 3;
  double angle_deg = 90;
  double weight = -1;  // < 0: off; any finite value
  bool enabled = true;
  Shape shape = Shape::kSquare;
  int internal = 4;
  Inner inner;
  template <class V>
  void Fields(V& v) {
    v.Group("Test");
    F2C_FIELD(v, count, "--count", AtLeast(2), "how many");
    F2C_FIELD(v, angle_deg, "--angle", AboveUpTo(0, 180), "an angle (deg)");
    F2C_FIELD(v, weight, "--weight", AnyFinite(), "a weight");
    F2C_FIELD(v, enabled, "--enabled,!--no-enabled", {}, "on or off");
    F2C_FIELD(v, shape, "--shape", {}, "a shape");
    F2C_FIELD(v, internal, "", Between(1, 64), "not a flag");
    F2C_NESTED(v, inner);
  }
  void Check() const { CheckFields(*this); }
};

std::string CheckMessage(const Outer& o) {
  try {
    o.Check();
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(Fields, TheDefaultsPass) { EXPECT_EQ(CheckMessage(Outer()), ""); }

TEST(Fields, EachBoundNamesTheFlagTheBoundAndTheValue) {
  Outer o;
  o.count = 1;
  EXPECT_EQ(CheckMessage(o), "--count: must be >= 2, got 1");
  o = Outer();
  o.angle_deg = 0;
  EXPECT_EQ(CheckMessage(o), "--angle: must be in (0, 180], got 0");
  o.angle_deg = 180;
  EXPECT_EQ(CheckMessage(o), "");
  o.angle_deg = 180.5;
  EXPECT_EQ(CheckMessage(o), "--angle: must be in (0, 180], got 180.5");
  o = Outer();
  o.weight = std::nan("");
  EXPECT_EQ(CheckMessage(o), "--weight: must be finite, got nan");
  o.weight = -1e300;
  EXPECT_EQ(CheckMessage(o), "");
  o = Outer();
  o.internal = 65;
  EXPECT_EQ(CheckMessage(o), "internal: must be in [1, 64], got 65");  // no flag: its key
}

TEST(Fields, NestedStructsRunTheirOwnCheck) {
  Outer o;
  o.inner.radius = 0;
  EXPECT_EQ(CheckMessage(o), "--radius: must be > 0, got 0");
}

TEST(Fields, BoundsAtTheirEdges) {
  EXPECT_TRUE(AtLeast(2).Admits(2));
  EXPECT_FALSE(AtLeast(2).Admits(1.999));
  EXPECT_FALSE(Positive().Admits(0));
  EXPECT_TRUE(Positive().Admits(1e-300));
  EXPECT_FALSE(Positive().Admits(std::numeric_limits<double>::infinity()));
  EXPECT_TRUE(Between(1, 64).Admits(64));
  EXPECT_FALSE(Between(1, 64).Admits(64.5));
  EXPECT_EQ(Between(0, 1).Describe(), "in [0, 1]");
  EXPECT_EQ((Bounds{.max = 5, .max_open = true}).Describe(), "< 5");
}

TEST(Fields, FlagNamesForMessages) {
  EXPECT_EQ(FieldName("--sift-loops,!--no-sift-loops", "enabled"), "--sift-loops");
  EXPECT_EQ(FieldName("!--no-fine-to-coarse", "fine_to_coarse"), "--no-fine-to-coarse");
  EXPECT_EQ(FieldName("", "attempts"), "attempts");
  EXPECT_EQ(FieldName(nullptr, "attempts"), "attempts");
}

TEST(Fields, EnumNamesBothWays) {
  EXPECT_STREQ(NameOf(Shape::kRound), "round");
  EXPECT_EQ(FromName<Shape>("square", "--shape"), Shape::kSquare);
  EXPECT_EQ(NamesOf<Shape>(), "round, square");
  try {
    FromName<Shape>("oval", "--shape");
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "--shape: unknown value 'oval' (round, square)");
  }
}

TEST(Fields, JsonHasEveryFieldByMemberNameWithEnumsByName) {
  Outer o;
  o.count = 7;
  o.shape = Shape::kRound;
  o.inner.radius = 2.5;
  const nlohmann::json j = FieldsToJson(o);
  EXPECT_EQ(j.size(), 7u);
  EXPECT_EQ(j["count"], 7);
  EXPECT_EQ(j["angle_deg"], 90.0);
  EXPECT_EQ(j["enabled"], true);
  EXPECT_EQ(j["shape"], "round");
  EXPECT_EQ(j["internal"], 4);
  EXPECT_EQ(j["inner"]["radius"], 2.5);
}

// Options by name, as the Python module passes its keyword arguments.
std::string SetMessage(Outer* o, const std::string& name, const FieldValue& value) {
  try {
    EXPECT_TRUE(SetFieldByFlag(*o, name, value)) << name;
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(Fields, SetByFlagReachesEveryKindOfField) {
  Outer o;
  EXPECT_TRUE(SetFieldByFlag(o, "count", FieldValue(int64_t{7})));
  EXPECT_EQ(o.count, 7);
  EXPECT_TRUE(SetFieldByFlag(o, "angle", FieldValue(45.5)));
  EXPECT_EQ(o.angle_deg, 45.5);
  EXPECT_TRUE(SetFieldByFlag(o, "angle", FieldValue(int64_t{30})));  // a whole number is a number
  EXPECT_EQ(o.angle_deg, 30);
  EXPECT_TRUE(SetFieldByFlag(o, "enabled", FieldValue(false)));
  EXPECT_FALSE(o.enabled);
  EXPECT_TRUE(SetFieldByFlag(o, "no-enabled", FieldValue(false)));  // the negated name
  EXPECT_TRUE(o.enabled);
  EXPECT_TRUE(SetFieldByFlag(o, "shape", FieldValue(std::string("round"))));
  EXPECT_EQ(o.shape, Shape::kRound);
  EXPECT_TRUE(SetFieldByFlag(o, "radius", FieldValue(2.0)));  // a nested struct's
  EXPECT_EQ(o.inner.radius, 2.0);
  EXPECT_FALSE(SetFieldByFlag(o, "internal", FieldValue(int64_t{5})));  // no flag, no name
  EXPECT_FALSE(SetFieldByFlag(o, "colour", FieldValue(int64_t{5})));
  EXPECT_EQ(o.internal, 4);
}

TEST(Fields, SetByFlagNamesTheOptionWhenTheValueIsOfTheWrongKind) {
  Outer o;
  EXPECT_EQ(SetMessage(&o, "count", FieldValue(2.5)), "--count: must be a whole number, got 2.5");
  EXPECT_EQ(SetMessage(&o, "count", FieldValue(int64_t{1} << 40)),
            "--count: must be a whole number within the option's type, got 1099511627776");
  EXPECT_EQ(SetMessage(&o, "angle", FieldValue(std::string("wide"))), "--angle: must be a number, got 'wide'");
  EXPECT_EQ(SetMessage(&o, "enabled", FieldValue(int64_t{1})), "--enabled: must be True or False, got 1");
  EXPECT_EQ(SetMessage(&o, "shape", FieldValue(std::string("oval"))), "--shape: unknown value 'oval' (round, square)");
  EXPECT_EQ(SetMessage(&o, "shape", FieldValue(true)), "--shape: must be one of round, square, got True");
  EXPECT_EQ(o.count, 3);  // a refused value leaves the field as it was
}

}  // namespace
}  // namespace f2c
