// A knob described once: a row of its struct's table (util/Knobs.h) is all that validate(), the command line
// (apps/rtsdf/KnobCli.h), the Python keywords and the generated docs (util/KnobDocs.h) need.
#include "KnobCli.h"
#include "jobs/Animate.h"
#include "jobs/Bake.h"
#include "jobs/RenderJob.h"
#include "util/KnobDocs.h"
#include "util/Knobs.h"
#include "view/Viewer.h"

#include <gtest/gtest.h>

#include <set>
#include <string>

namespace rtsdf {
namespace {

enum class Flavour { Plain, Spiced };

/// A settings struct that exists only here: every front end must see its knobs through the table alone.
struct ToySettings {
  int count = 3;
  double gain = -1.0;
  Flavour flavour = Flavour::Plain;
  bool loud = false;
  void validate() const { validateKnobs(*this); }
};

} // namespace

template <> struct EnumNames<Flavour> {
  static constexpr const char* kSetting = "toy flavour";
  static constexpr std::pair<const char*, Flavour> kValues[] = {{"plain", Flavour::Plain},
                                                                {"spiced", Flavour::Spiced}};
};

template <> struct KnobTable<ToySettings> {
  using S = ToySettings;
  static constexpr auto kKnobs = std::make_tuple(
      knob("toy count", &S::count, "-c,--count", KnobRange::closed(1, 10), "Toys in the box [n]"),
      knob("toy gain", &S::gain, "--gain", KnobRange::atLeast(0).orNegative("by the count"), "Gain of each toy"),
      enumKnob(&S::flavour, "--flavour", "How the toys taste"),
      flagKnob("loud", &S::loud, "--loud", "Toys squeak", "squeaky"));
};

namespace {

std::string refusal(const ToySettings& s) {
  try {
    s.validate();
  } catch (const SettingError& e) {
    return e.setting() + ": " + e.what();
  }
  return {};
}

TEST(Knobs, ValidateChecksEveryRowsRange) {
  ToySettings s;
  EXPECT_EQ(refusal(s), "");
  s.count = 11;
  EXPECT_EQ(refusal(s), "toy count: toy count 11 is out of range [1, 10]");
  s.count = 10;
  s.gain = 0.5;
  EXPECT_EQ(refusal(s), "");
  s.gain = -3.0; // the special value: automatic
  EXPECT_EQ(refusal(s), "");
  s.gain = std::nan("");
  EXPECT_EQ(refusal(s), "toy gain: toy gain nan must be finite and >= 0 (or < 0: by the count)");
  s.gain = -INFINITY;
  EXPECT_NE(refusal(s), "");
}

/// The command line's parse of @a args for a command bound from ToySettings' table; "" when accepted.
std::string parse(ToySettings& s, const std::vector<std::string>& args, std::string* help = nullptr) {
  CLI::App app("toys");
  app::SettingFlags flags;
  app::bindKnobs(&app, s, flags);
  EXPECT_EQ(flags.flagOf("toy count"), "--count");
  EXPECT_EQ(flags.flagOf("toy flavour"), "--flavour");
  if (help) *help = app.help();
  std::vector<std::string> reversed(args.rbegin(), args.rend());
  try {
    app.parse(reversed);
  } catch (const CLI::ParseError& e) {
    return e.what();
  }
  return {};
}

TEST(Knobs, TheCommandLineBindsEveryRowWithItsHelpRangeAndDefault) {
  ToySettings s;
  std::string help;
  EXPECT_EQ(parse(s, {}, &help), "");
  for (const char* text : {"-c,--count", "Toys in the box [n]", "--gain", "(default: by the count)", "--flavour",
                           "{plain|spiced}", "--loud", "Toys squeak"})
    EXPECT_NE(help.find(text), std::string::npos) << text << " not in\n" << help;
  EXPECT_NE(help.find("INT:in [1, 10]=3"), std::string::npos) << "the count's range and default: " << help;
  EXPECT_EQ(parse(s, {"--count", "7", "--gain", "2", "--flavour", "spiced", "--loud"}), "");
  EXPECT_EQ(s.count, 7);
  EXPECT_EQ(s.gain, 2.0);
  EXPECT_EQ(s.flavour, Flavour::Spiced);
  EXPECT_TRUE(s.loud);
  EXPECT_NE(parse(s, {"--count", "11"}).find("11 is out of range: it must be in [1, 10]"), std::string::npos);
  EXPECT_NE(parse(s, {"--gain", "-1"}).find("-1 is out of range: it must be >= 0"), std::string::npos);
  EXPECT_NE(parse(s, {"--count", "many"}).find("'many' is not a number"), std::string::npos);
  EXPECT_NE(parse(s, {"--flavour", "sweet"}).find("'sweet' is not one of plain or spiced"), std::string::npos);
}

TEST(Knobs, PythonKeywordsComeFromTheLongFlagOrTheRow) {
  ToySettings s;
  std::set<std::string> keywords;
  forEachKnob<ToySettings>([&](const auto& k) { keywords.insert(keywordOf(k)); });
  EXPECT_EQ(keywords, (std::set<std::string>{"count", "gain", "flavour", "squeaky"}));
  int visited = 0;
  EXPECT_TRUE(visitKnobByKeyword(s, "count", [&](const auto&, auto& member) {
    if constexpr (std::is_same_v<std::decay_t<decltype(member)>, int>) member = 9;
    ++visited;
  }));
  EXPECT_EQ(visited, 1);
  EXPECT_EQ(s.count, 9);
  EXPECT_FALSE(visitKnobByKeyword(s, "colour", [](const auto&, auto&) {}));
}

TEST(Knobs, TheDocsShowEveryRow) {
  ToySettings loud;
  loud.loud = true;
  const std::string md = knobMarkdown<ToySettings>({{"quiet", ToySettings{}}, {"loud", loud}}, true);
  EXPECT_NE(md.find("| setting | flag | Python | quiet | loud | range | meaning |"), std::string::npos) << md;
  EXPECT_NE(md.find("| toy count | `-c,--count` | `count` | 3 | 3 | in [1, 10] | Toys in the box [n] |"),
            std::string::npos) << md;
  EXPECT_NE(md.find("| toy gain | `--gain` | `gain` | auto | auto | >= 0; < 0: by the count | Gain of each toy |"),
            std::string::npos) << md;
  EXPECT_NE(md.find("| toy flavour | `--flavour` | `flavour` | plain | plain | plain or spiced |"), std::string::npos)
      << md;
  EXPECT_NE(md.find("| loud | `--loud` | `squeaky` | off | on | on, off | Toys squeak |"), std::string::npos) << md;
}

/// Every default of a real table lies in its row's range (or is its special value), and no two rows of a
/// struct share a setting name, a flag or a keyword.
template <class S> void expectConsistentTable(const S& defaults) {
  EXPECT_NO_THROW(validateKnobs(defaults));
  std::set<std::string> settings, flags, keywords;
  forEachKnob<S>([&](const auto& k) {
    EXPECT_TRUE(settings.insert(k.setting).second) << k.setting;
    EXPECT_TRUE(keywords.insert(keywordOf(k)).second) << k.setting;
    if (*k.flags) {
      EXPECT_TRUE(flags.insert(longFlag(k.flags)).second) << k.flags;
    }
    EXPECT_NE(std::string(k.help), "") << k.setting;
  });
}

/// A length knob: scene units or voxels, one row like any other.
struct ToyLengths {
  Length reach = Length::voxels(3);
  void validate() const { validateKnobs(*this); }
};
} // namespace
template <> struct KnobTable<ToyLengths> {
  using S = ToyLengths;
  static constexpr auto kKnobs =
      std::make_tuple(knob("toy reach", &S::reach, "--reach", KnobRange::atLeast(0), "How far a toy reaches"));
};
namespace {

/// The command line's parse of @a args for a command bound from S's table; "" when accepted.
template <class S> std::string parseAny(S& s, const std::vector<std::string>& args, std::string* help = nullptr) {
  CLI::App app("toys");
  app::SettingFlags flags;
  app::bindKnobs(&app, s, flags);
  if (help) *help = app.help();
  std::vector<std::string> reversed(args.rbegin(), args.rend());
  try {
    app.parse(reversed);
  } catch (const CLI::ParseError& e) {
    return e.what();
  }
  return {};
}

TEST(Knobs, ALengthIsGivenInSceneUnitsOrVoxels) {
  EXPECT_EQ(Length::parse("0.25")->text(), "0.25");
  EXPECT_TRUE(Length::parse("3vox")->inVoxels());
  EXPECT_EQ(Length::parse("2.5 voxels")->value, 2.5);
  EXPECT_FALSE(Length::parse("3vx"));
  EXPECT_FALSE(Length::parse("vox"));
  EXPECT_EQ(Length::voxels(4).sceneUnits(0.5), 2.0);
  EXPECT_EQ(Length(0.3).sceneUnits(0.5), 0.3);
  EXPECT_THROW((void)double(Length::voxels(1)), std::logic_error) << "an unresolved length read as a number";

  ToyLengths s;
  std::string help;
  EXPECT_EQ(parseAny(s, {}, &help), "");
  EXPECT_NE(help.find("3vox"), std::string::npos) << help;
  EXPECT_NE(help.find(kLengthSyntax), std::string::npos) << help;
  EXPECT_EQ(parseAny(s, {"--reach", "0.25"}), "");
  EXPECT_FALSE(s.reach.inVoxels());
  EXPECT_EQ(s.reach.value, 0.25);
  EXPECT_EQ(parseAny(s, {"--reach", "2vox"}), "");
  EXPECT_TRUE(s.reach.inVoxels());
  EXPECT_EQ(s.reach.value, 2.0);
  EXPECT_NE(parseAny(s, {"--reach", "2vx"}).find("'2vx' is not a length"), std::string::npos);
  EXPECT_NE(parseAny(s, {"--reach", "-1vox"}).find("out of range"), std::string::npos);
  s.reach = Length::voxels(-1);
  EXPECT_THROW(s.validate(), SettingError);
  const std::string md = knobMarkdown<ToyLengths>({{"default", ToyLengths{}}}, true);
  EXPECT_NE(md.find("| 3vox |"), std::string::npos) << md;
  EXPECT_NE(md.find(kLengthSyntax), std::string::npos) << md;
}

TEST(Knobs, AFlagThatTurnsAKnobOffShowsNoValueInTheHelp) {
  TaaSettings taa;
  std::string help;
  EXPECT_EQ(parseAny(taa, {}, &help), "");
  EXPECT_NE(help.find("--no-taa"), std::string::npos) << help;
  EXPECT_EQ(help.find("{false}"), std::string::npos) << help;
  EXPECT_TRUE(taa.enabled);
  EXPECT_EQ(parseAny(taa, {"--no-taa"}), "");
  EXPECT_FALSE(taa.enabled);
}

TEST(Knobs, RealTablesAreConsistent) {
  expectConsistentTable(PipelineSettings{});
  expectConsistentTable(AnimateOptions{}.pipeline);
  expectConsistentTable(RenderJobOptions{}.render.pipeline);
  expectConsistentTable(BakeOptions{});
  expectConsistentTable(AnimateOptions{});
  expectConsistentTable(RenderJobOptions{});
  expectConsistentTable(ViewOptions{});
  expectConsistentTable(RenderSettings{});
  expectConsistentTable(SdfShadowSettings{});
  expectConsistentTable(ShadowMapSettings{});
  expectConsistentTable(TaaSettings{});
  expectConsistentTable(RayTracedShadowSettings{});
}

} // namespace
} // namespace rtsdf
