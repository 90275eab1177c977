// models/: plausibility of every model on random and extreme directions, spec strings, bad input.
#include <cmath>
#include <numbers>
#include <random>

#include <gtest/gtest.h>

#include "tests/test_support.h"

#include "models/kp_lobes.h"
#include "models/mixture.h"
#include "models/registry.h"
#include "models/spec.h"
#include "util/error.h"

namespace ganzfeld {
namespace {

using std::numbers::pi;

// Every registered model at its defaults and at the extremes of its parameters.
const std::vector<std::string> kSpecs{"lambert",
                                      "minnaert:xi=0",
                                      "minnaert:xi=1e-6",
                                      "minnaert:xi=0.3",
                                      "minnaert:xi=50",
                                      "specular:alpha=1",
                                      "specular:alpha=8",
                                      "specular:alpha=1000",
                                      "specular:alpha=2.5",
                                      "backscatter:alpha=1",
                                      "backscatter:alpha=1000",
                                      "perfect-backscatter:alpha=2",
                                      "perfect-backscatter:alpha=1000",
                                      "asperity:alpha=1",
                                      "asperity:alpha=1000",
                                      "0.7*minnaert:xi=1 + 0.3*specular:alpha=8"};

Vec3 from_cos(double c, double phi) {
  const double s = std::sqrt(std::max(0.0, 1.0 - c * c));
  return {s * std::cos(phi), s * std::sin(phi), c};
}

std::vector<Vec3> test_directions() {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<Vec3> dirs;
  for (double c : {0.0, 1e-6, 1e-3, 0.5, 1.0 - 1e-12, 1.0})
    for (double phi : {0.0, 0.5 * pi, pi}) dirs.push_back(from_cos(c, phi));
  for (int k = 0; k < 60; ++k) dirs.push_back(from_cos(u(rng), 2 * pi * u(rng)));
  return dirs;
}

TEST(Models, EveryModelIsFiniteNonNegativeReciprocalAndZeroBelowTheHorizon) {
  const auto dirs = test_directions();
  for (const auto& spec : kSpecs)
    testing_support::expect_finite_non_negative_reciprocal(*parse_model(spec), dirs, spec);
}

TEST(Models, MinnaertWithZeroExponentIsLambert) {
  const auto dirs = test_directions();
  const Minnaert minnaert(0.0);
  const Lambert lambert;
  for (const Vec3& i : dirs)
    for (const Vec3& j : dirs) EXPECT_DOUBLE_EQ(minnaert.f(i, j), lambert.f(i, j));
}

TEST(Models, PerfectBackscatterRetroRadianceIsConstant) {
  const PerfectBackscatter m(3);
  const double expected = perfect_backscatter::retro_radiance(3);
  constexpr double kRelative = 1e-14;  // a few ulps of the formula's rounding
  for (double c : {1e-6, 0.1, 0.5, 1.0}) {
    const Vec3 i = from_cos(c, 0.3);
    EXPECT_NEAR(c * m.f(i, i), expected, kRelative * expected) << c;
  }
}

TEST(Models, MixtureIsTheNormalizedWeightedSum) {
  const ModelPtr mix = parse_model("2*minnaert:xi=1 + 6*specular:alpha=8");
  const Minnaert d(1);
  const Specular s(8);
  const Vec3 i = from_cos(0.6, 0), j = from_cos(0.7, 2.5);
  EXPECT_DOUBLE_EQ(mix->f(i, j), 0.25 * d.f(i, j) + 0.75 * s.f(i, j));
  EXPECT_EQ(mix->spec(), "0.25*minnaert:xi=1 + 0.75*specular:alpha=8");
  EXPECT_TRUE(mix->traits().reciprocal);
  EXPECT_EQ(mix->traits().energy, EnergyClass::plausible);
}

TEST(Spec, CanonicalFormRoundTripsAndFillsDefaults) {
  EXPECT_EQ(parse_model("minnaert")->spec(), "minnaert:xi=1");
  EXPECT_EQ(parse_model(" specular : alpha = 8 ")->spec(), "specular:alpha=8");
  EXPECT_EQ(parse_model("specular:alpha=1e+3")->spec(), "specular:alpha=1000");
  for (const auto& spec : kSpecs) {
    const std::string canonical = parse_model(spec)->spec();
    EXPECT_EQ(parse_model(canonical)->spec(), canonical) << spec;
  }
}

/// Specs of `info` that the registry allows: its example (every parameter at its default, a
/// required data file as DATA), each parameter alone at its middle and each choice, and with
/// `ends`, each parameter alone at the ends of its range.
std::vector<ModelSpec> registry_specs(const ModelInfo& info, bool ends) {
  ModelSpec example{info.name, {}, info.make_with_file && !info.file_optional ? "DATA" : ""};
  for (const ParamInfo& p : info.parameters)
    if (!p.optional) example.values[p.name] = p.default_value;
  std::vector<ModelSpec> specs{example};
  for (const ParamInfo& p : info.parameters) {
    std::vector<double> values;
    if (p.type == ParamType::choice)
      for (std::size_t k = 0; k < p.choices.size(); ++k) values.push_back(static_cast<double>(k));
    else values = {p.type == ParamType::integer ? std::floor(0.5 * (p.min + p.max)) : 0.5 * (p.min + p.max)};
    if (ends && p.type != ParamType::choice)
      values.insert(values.end(), {p.min_exclusive ? std::nextafter(p.min, p.max) : p.min, p.max});
    for (const double value : values) specs.push_back({info.name, {{p.name, value}}, example.file});
  }
  return specs;
}

// The one grammar: every registered model's specs and a mixture of all of them read back as
// they were written (spec -> Spec -> text -> the same Spec), and every model's canonical spec
// (built at its defaults and middles: ggx-ms builds an energy table per alpha) is the text of
// its parsed self.
TEST(Spec, EveryRegisteredModelAndAMixtureOfAllRoundTrip) {
  Spec all;
  for (const ModelInfo& info : model_catalogue()) {
    for (const ModelSpec& model : registry_specs(info, true)) {
      const std::string text = spec_text(model);
      const Spec parsed = parse_spec(text);
      ASSERT_EQ(parsed.terms.size(), 1u) << text;
      EXPECT_EQ(parsed.terms.front().model, model) << text;
      EXPECT_EQ(spec_text(parsed), text);
    }
    int built = 0;
    for (const ModelSpec& model : registry_specs(info, false)) {
      if (!model.file.empty()) continue;  // no data file to build from
      std::string canonical;
      try {
        canonical = make_model(model)->spec();
      } catch (const InputError&) {  // a combination the factory refuses (cook-torrance: kd + ks > 1)
        continue;
      }
      ++built;
      EXPECT_EQ(spec_text(parse_spec(canonical)), canonical) << spec_text(model);
      EXPECT_EQ(parse_model(canonical)->spec(), canonical) << spec_text(model);
    }
    EXPECT_TRUE(built > 0 || (info.make_with_file && !info.file_optional)) << info.name << ": none built";
    all.terms.push_back({1.0 + static_cast<double>(all.terms.size()), registry_specs(info, false).front()});
  }
  const Spec mixture = parse_spec(spec_text(all));  // normalizes the weights 1, 2, ..., n
  const double n = static_cast<double>(model_catalogue().size());
  ASSERT_EQ(mixture.terms.size(), model_catalogue().size());
  EXPECT_NEAR(mixture.terms.back().weight, n / (n * (n + 1) / 2), 1e-15);  // weight n of 1 + 2 + ... + n
  EXPECT_EQ(parse_spec(spec_text(mixture)), mixture);
  EXPECT_TRUE(mixture.names_file());
}

// An alternative is written in the place of the parameter it stands in for, whatever the order
// it was given in, so a model's canonical spec does not depend on how the spec was typed.
TEST(Spec, AlternativesAreWrittenInTheirParametersPlace) {
  EXPECT_EQ(spec_text(parse_spec("hvd-empirical:rr=1,rsv=0.2,k=0.3,rsu=1,eta=1.5")),
            "hvd-empirical:eta=1.5,k=0.3,rsu=1,rsv=0.2,rr=1");
  EXPECT_EQ(parse_model("hvd-empirical:cd=1,f0=0.5,k=0.4,ns=50,nr=10,rsu=1,rsv=0.2")->spec(),
            "hvd-empirical:cd=1,f0=0.5,k=0.4,ns=50,nr=10,rsu=1,rsv=0.2,rr=1");
  EXPECT_EQ(parse_model("ggx:f0=0.5,alpha_y=0.3,alpha_x=0.1")->spec(),
            "ggx:alpha_x=0.1,alpha_y=0.3,f0=0.5,g2=height-correlated");
}

/// Expects an InputError whose one-line message contains every fragment.
void expect_refused(const std::string& spec, const std::vector<std::string>& fragments) {
  try {
    parse_model(spec);
    ADD_FAILURE() << "accepted: " << spec;
  } catch (const InputError& e) {
    const std::string message = e.what();
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
    for (const auto& fragment : fragments)
      EXPECT_NE(message.find(fragment), std::string::npos) << "'" << message << "' lacks '" << fragment << "'";
  }
}

// fuzz/corpus/spec/crash-mixture-canonical-spec-round-trip: normalized weights sum to 1 only within
// rounding; normalizing them again must not change their last digits (the spec is the identity).
TEST(Spec, MixtureCanonicalFormRoundTrips) {
  for (const char* spec : {"2.5*lambert+0.26*phong+0.25*ggx:alpha=0.1", "1*lambert + 3*minnaert:xi=1 + 7*phong",
                           "0.1*lambert + 0.2*lambert + 0.3*lambert + 1e-9*phong"}) {
    const std::string canonical = parse_model(spec)->spec();
    EXPECT_EQ(parse_model(canonical)->spec(), canonical) << spec;
  }
}

TEST(Spec, BadNamesAndSyntaxAreRefusedWithWhatIsAllowed) {
  expect_refused("no-such-model", {"'no-such-model'", "lambert", "asperity"});
  expect_refused("specular:beta=2", {"'beta'", "alpha"});
  expect_refused("specular:alpha", {"KEY=VALUE"});
  expect_refused("specular:alpha=2,alpha=3", {"twice"});
  expect_refused("lambert:xi=1", {"'xi'", "none"});
}

TEST(Spec, BadValuesAreRefusedWithTheValueAndTheRange) {
  expect_refused("specular:alpha=0.5", {"alpha=0.5", "[1, 10000]"});
  expect_refused("specular:alpha=nan", {"alpha=nan", "finite"});
  expect_refused("specular:alpha=inf", {"alpha=inf"});
  expect_refused("minnaert:xi=-1", {"xi=-1", "[0, 1000]"});
  expect_refused("specular:alpha=eight", {"'eight'", "not a number"});
}

// Each weight finite, their sum not: normalized, the weights were NaN and the spec read
// "-nan*lambert + -nan*lambert".
TEST(Spec, MixtureWeightsWhoseSumOverflowsAreRefused) {
  expect_refused("1.7e308*lambert + 1.7e308*lambert", {"1.7e308*lambert", "sum to more than the largest number"});
  expect_refused("1e308*lambert + 1e308*minnaert:xi=1 + 1e308*phong", {"sum to more than"});
  EXPECT_EQ(parse_model("1e307*lambert + 1e307*minnaert:xi=1")->spec(), "0.5*lambert + 0.5*minnaert:xi=1");
}

TEST(Spec, IntegerParametersAreRefusedOutsideTheirSet) {
  expect_refused("perfect-backscatter:alpha=2.5", {"alpha=2.5", "integer"});
  expect_refused("perfect-backscatter:alpha=1", {"alpha=1", "[2, 10000]"});
}

TEST(Spec, EmptyAndBadMixturesAreRefused) {
  expect_refused("", {"empty"});
  expect_refused("0.5*lambert + ", {"empty term"});
  expect_refused("-1*lambert + minnaert", {"-1", "> 0"});
  expect_refused("x*lambert", {"'x'"});
}

// fuzz/corpus/spec/crash-newline-in-unknown-model-name: a quoted line break stays off the message.
TEST(Spec, LineBreaksNeverReachTheOneLineMessage) {
  expect_refused(std::string("tab\n\0\0\0ed:", 9), {"unknown model 'tab "});
  expect_refused("specular:alpha=1\r\n2", {"'1  2'"});
}

// A device is not a data file (/dev/zero was read for ever).
TEST(Spec, DevicesAreNotDataFiles) {
  for (const char* model : {"tabulated", "merl", "beard-maxwell"})
    expect_refused(std::string(model) + ":file=/dev/zero", {"/dev/zero", "not a regular file"});
}

}  // namespace
}  // namespace ganzfeld
