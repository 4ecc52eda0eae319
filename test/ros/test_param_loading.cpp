// Parameters: the shipped YAML against params.hpp, parsing by key, and dynamic_reconfigure's
// Config to Params and back.
#include <gtest/gtest.h>

#include <boost/any.hpp>
#include <cmath>
#include <fstream>
#include <map>

#include "ring_curvature/ros/param_loading.hpp"
#include "ring_curvature/ros/param_table.hpp"

using namespace ring_curvature;

namespace
{

// Collects every key and value as text, to compare two Params key by key.
class Dump : public ParamVisitor
{
public:
  bool visit(const char* k, float& v) override { return put(k, std::to_string(v)); }
  bool visit(const char* k, int& v) override { return put(k, std::to_string(v)); }
  bool visit(const char* k, bool& v) override { return put(k, v ? "true" : "false"); }
  bool visit(const char* k, std::string& v) override { return put(k, v); }
  std::map<std::string, std::string> values;

private:
  bool put(const char* k, const std::string& v)
  {
    values[k] = v;
    return true;
  }
};

std::map<std::string, std::string> dump(Params p)
{
  Dump d;
  EXPECT_TRUE(forEachParam(p, d).ok);
  return d.values;
}

template <typename T>
bool copyField(const RingCurvatureConfig::AbstractParamDescription& d, const RingCurvatureConfig& from,
               RingCurvatureConfig& to)
{
  const auto* typed = dynamic_cast<const RingCurvatureConfig::ParamDescription<T>*>(&d);
  if (typed) to.*(typed->field) = from.*(typed->field);
  return typed != nullptr;
}

// Sets the one key that `d` describes in `to` to its value in `from`.
void setFrom(const RingCurvatureConfig::AbstractParamDescription& d, const RingCurvatureConfig& from,
             RingCurvatureConfig& to)
{
  EXPECT_TRUE(copyField<double>(d, from, to) || copyField<int>(d, from, to) || copyField<bool>(d, from, to)) << d.name;
}

}  // namespace

TEST(Params, ShippedYamlHoldsTheCoreDefaults)
{
  Params p;
  const Status s = loadParamsFile(std::string(RC_SOURCE_DIR) + "/config/ring_curvature.yaml", p);
  ASSERT_TRUE(s.ok) << s.message;
  EXPECT_EQ(dump(Params()), dump(p)) << "config/ring_curvature.yaml drifted from params.hpp";
}

TEST(Params, YamlEveryKeyPresent)
{
  std::map<std::string, std::string> in_file;
  std::ifstream f(std::string(RC_SOURCE_DIR) + "/config/ring_curvature.yaml");
  std::string line;
  while (std::getline(f, line))
    if (!line.empty() && line[0] != '#' && line.find(':') != std::string::npos)
      in_file[line.substr(0, line.find(':'))] = "";
  for (const auto& kv : dump(Params()))
    EXPECT_EQ(1u, in_file.count(kv.first)) << "key " << kv.first << " missing from config/ring_curvature.yaml";
}

TEST(Params, StringsAreParsedAndCheckedByKey)
{
  Params p;
  EXPECT_TRUE(applyParamStrings({{"curvature_mode", "paper"}, {"min_primitive_points", "7"}}, p).ok);
  EXPECT_EQ(CurvatureMode::Paper, p.curvature_mode);
  EXPECT_EQ(7, p.min_primitive_points);
  Status s = applyParamStrings({{"curvature_mode", "bogus"}}, p);
  EXPECT_NE(std::string::npos, s.message.find("curvature_mode")) << s.message;
  s = applyParamStrings({{"min_range", "near"}}, p);
  EXPECT_NE(std::string::npos, s.message.find("min_range")) << s.message;
  s = applyParamStrings({{"min_rnage", "1"}}, p);
  EXPECT_NE(std::string::npos, s.message.find("min_rnage")) << s.message;
  s = applyParamStrings({{"smoothness_window", "-4"}}, p);
  EXPECT_FALSE(s.ok) << "validate() must reject a negative window";
}

TEST(Params, ReconfigureRoundTrip)
{
  Params p;
  p.curvature_mode = CurvatureMode::Developed;
  p.robust_k = 4.5f;
  p.max_rings = 64;  // not live: must survive from the base
  const Params q = fromConfig(toConfig(p), p);
  EXPECT_EQ(dump(p), dump(q));
}

// Every key of cfg/RingCurvature.cfg, set alone to a value other than its default, reaches
// Params and comes back: no live key is dropped in either direction or copied to another.
TEST(Params, EveryLiveKeyReachesParamsAndComesBack)
{
  using Config = RingCurvatureConfig;
  const Params base;
  const Config min = Config::__getMin__(), max = Config::__getMax__(), defaults = toConfig(base);
  const auto number = [](const Config::AbstractParamDescriptionConstPtr& d, const Config& c) {
    boost::any v;
    d->getValue(c, v);
    if (d->type == "double") return boost::any_cast<double>(v);
    if (d->type == "int") return static_cast<double>(boost::any_cast<int>(v));
    return boost::any_cast<bool>(v) ? 1.0 : 0.0;
  };
  const auto& all = Config::__getParamDescriptions__();
  ASSERT_GT(all.size(), 40u);
  for (const auto& d : all)
  {
    ASSERT_TRUE(d->type == "double" || d->type == "int" || d->type == "bool") << d->name << ": " << d->type;
    EXPECT_TRUE(isParamKey(d->name)) << d->name << " is in the .cfg but not a key of Params";
    // its maximum, or its minimum where the maximum is the default
    const Config& pick = number(d, max) != number(d, defaults) ? max : min;
    ASSERT_NE(number(d, pick), number(d, defaults)) << d->name;
    Config changed = defaults;
    setFrom(*d, pick, changed);
    const Config back = toConfig(fromConfig(changed, base));
    for (const auto& other : all)
    {
      const double want = number(other, changed), got = number(other, back);
      // (doubles pass through Params' floats)
      EXPECT_NEAR(want, got, 1e-6 * std::max(1.0, std::fabs(want))) << other->name << " after setting " << d->name;
    }
  }
}
