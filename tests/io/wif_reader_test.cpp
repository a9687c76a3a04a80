// The WIF reader, case by case (io/wif_reader.h, docs/formats/wif.md). The refusals
// of whole files are the catalogue tests/cli/bad_wifs/; real files from
// weaving programs are checked by tests/cli/wif_real.sh.

#include "io/wif_reader.h"

#include <cmath>
#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>

#include "core/util/error.h"
#include "io/cloth_spec_json.h"

namespace clothbake::io {
namespace {

// A small valid file; each test edits a copy.
const std::string k_base = R"([WIF]
Version=1.1
Source Program=test
[CONTENTS]
WEAVING=yes
WARP=yes
WEFT=yes
THREADING=yes
TIEUP=yes
TREADLING=yes
[WEAVING]
Shafts=2
Treadles=2
[WARP]
Threads=2
[WEFT]
Threads=2
[THREADING]
1=1
2=2
[TIEUP]
1=1
2=2
[TREADLING]
1=1
2=2
)";

std::string with(std::string text, const std::string& from, const std::string& to) {
  const size_t at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  return text.replace(at, from.size(), to);
}

std::string error_of(const std::string& text) {
  try {
    (void)parse_wif(text, "t.wif");
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), "t.wif");
    return e.field() + " | " + e.message();
  }
  return "(no error)";
}

TEST(WifReader, ReadsTheDrawdown) {
  const WifFile w = parse_wif(k_base, "t.wif");
  EXPECT_EQ(w.source_program, "test");
  EXPECT_EQ(drawdown(w.loom), (std::vector<std::vector<int>>{{1, 0}, {0, 1}}));
  EXPECT_TRUE(w.loom.rising_shed);  // the default when [WEAVING] has no Rising Shed
}

TEST(WifReader, KeysCaseSpacesCommentsAndPrivateSections) {
  std::string t = with(k_base, "[WEAVING]\nShafts=2", "; a comment line\n[weaving]\n  sHaFtS  =  2  ; after a value");
  t = with(t, "[TREADLING]", "[PRIVATE SOMEPROGRAM SETTINGS]\nColour Of The Day=mauve\n[treadling]");
  t = with(t, "Treadles=2", "Treadles = 2\nRISING  SHED = no");
  const WifFile w = parse_wif(t, "t.wif");
  EXPECT_EQ(w.loom.shafts, 2);
  EXPECT_FALSE(w.loom.rising_shed);
  EXPECT_EQ(drawdown(w.loom), (std::vector<std::vector<int>>{{0, 1}, {1, 0}}));
}

TEST(WifReader, BooleansInEveryForm) {
  for (const char* yes : {"yes", "TRUE", "1", "On"}) {
    const WifFile w = parse_wif(with(k_base, "Treadles=2", std::string("Treadles=2\nRising Shed=") + yes), "t.wif");
    EXPECT_TRUE(w.loom.rising_shed) << yes;
  }
  for (const char* no : {"no", "False", "0", "OFF"}) {
    const WifFile w = parse_wif(with(k_base, "Treadles=2", std::string("Treadles=2\nRising Shed=") + no), "t.wif");
    EXPECT_FALSE(w.loom.rising_shed) << no;
  }
  EXPECT_EQ(error_of(with(k_base, "Treadles=2", "Treadles=2\nRising Shed=maybe")),
            "[WEAVING] line 14 | RISING SHED: expected yes/no (true/false, 1/0, on/off), got 'maybe'");
}

TEST(WifReader, LiftplanInsteadOfTreadling) {
  const std::string t = with(with(k_base, "[TIEUP]\n1=1\n2=2\n[TREADLING]\n1=1\n2=2\n",
                                  "[LIFTPLAN]\n1=2\n2=1,2\n"),
                             "TIEUP=yes\nTREADLING=yes", "LIFTPLAN=yes");
  const WifFile w = parse_wif(t, "t.wif");
  EXPECT_TRUE(w.loom.has_liftplan);
  EXPECT_EQ(drawdown(w.loom), (std::vector<std::vector<int>>{{0, 1}, {1, 1}}));
}

TEST(WifReader, ZeroAndEmptyEntriesLiftNothing) {
  const std::string t = with(k_base, "[TREADLING]\n1=1\n2=2\n", "[TREADLING]\n1=0\n2=\n");
  EXPECT_EQ(drawdown(parse_wif(t, "t.wif").loom), (std::vector<std::vector<int>>{{0, 0}, {0, 0}}));
  const std::string u = with(k_base, "[THREADING]\n1=1\n2=2\n", "[THREADING]\n1=0\n");
  EXPECT_EQ(drawdown(parse_wif(u, "t.wif").loom), (std::vector<std::vector<int>>{{0, 0}, {0, 0}}));
}

TEST(WifReader, PaletteRangeAndColourTable) {
  std::string t = with(k_base, "[WARP]\nThreads=2",
                       "[COLOR PALETTE]\nRange=0,999\nEntries=2\nForm=RGB\n[COLOR TABLE]\n1=999,0,0\n"
                       "2=0,0,999\n[WARP]\nThreads=2\nColor=1");
  t = with(t, "[WEFT]\nThreads=2", "[WEFT]\nThreads=2\nColor=2\n[WEFT COLORS]\n2=1");
  const ClothSpec s = apply_wif(parse_wif(t, "t.wif"), ClothSpec{});
  EXPECT_EQ(s.warp.color, Imath::V3f(1, 0, 0));
  EXPECT_TRUE(s.warp.colors.empty());
  ASSERT_EQ(s.weft.colors.size(), 2u);
  EXPECT_EQ(s.weft.colors[0], Imath::V3f(0, 0, 1));  // the family colour, filled in
  EXPECT_EQ(s.weft.colors[1], Imath::V3f(1, 0, 0));
  // Mid-grey in 0-65535 is the same linear value as in 0-255's 127.5.
  const std::string g = with(with(t, "Range=0,999", "Range=0,65535"), "1=999,0,0", "1=32767.5,32767.5,32767.5");
  const ClothSpec sg = apply_wif(parse_wif(g, "t.wif"), ClothSpec{});
  EXPECT_NEAR(sg.warp.color.x, std::pow((0.5 + 0.055) / 1.055, 2.4), 1e-6);
  // Without a Range: 0-255.
  const std::string d =
      with(with(with(t, "Range=0,999\n", ""), "1=999,0,0", "1=255,0,0"), "2=0,0,999", "2=0,0,255");
  EXPECT_EQ(apply_wif(parse_wif(d, "t.wif"), ClothSpec{}).warp.color, Imath::V3f(1, 0, 0));
}

TEST(WifReader, UnitsSpacingAndThickness) {
  const std::string t = with(with(k_base, "[WARP]\nThreads=2", "[WARP]\nThreads=2\nUnits=Inches\nSpacing=0.05\nThickness=0.04\n[WARP SPACING]\n2=0.1"),
                             "[WEFT]\nThreads=2", "[WEFT]\nThreads=2\nUnits=decipoints\nSpacing=20");
  const ClothSpec s = apply_wif(parse_wif(t, "t.wif"), ClothSpec{});
  EXPECT_FLOAT_EQ(s.warp.spacing_mm, 1.27f);
  EXPECT_FLOAT_EQ(s.warp.width_mm, 1.016f);
  EXPECT_FLOAT_EQ(s.warp.thickness_mm, 1.016f * 0.18f / 0.44f);  // the default's aspect
  ASSERT_EQ(s.warp.spacings_mm.size(), 2u);
  EXPECT_FLOAT_EQ(s.warp.spacings_mm[0], 1.27f);
  EXPECT_FLOAT_EQ(s.warp.spacings_mm[1], 2.54f);
  EXPECT_FLOAT_EQ(s.weft.spacing_mm, 20.0f * 25.4f / 720.0f);
  EXPECT_FLOAT_EQ(s.weft.width_mm, 0.88f * s.weft.spacing_mm);  // no Thickness: scales with spacing
  // Centimetres when Units is absent.
  const std::string c = with(k_base, "[WARP]\nThreads=2", "[WARP]\nThreads=2\nSpacing=0.05");
  EXPECT_FLOAT_EQ(apply_wif(parse_wif(c, "t.wif"), ClothSpec{}).warp.spacing_mm, 0.5f);
}

TEST(WifReader, RefusalsNameSectionAndLine) {
  EXPECT_EQ(error_of(with(k_base, "1=1\n2=2\n[TIEUP]", "1=1\n2=3\n[TIEUP]")),
            "[THREADING] line 20 | names 3, above [WEAVING] Shafts=2");
  EXPECT_EQ(error_of(with(k_base, "[TREADLING]\n1=1", "[TREADLING]\n1=5")),
            "[TREADLING] line 25 | names 5, above [WEAVING] Treadles=2");
  EXPECT_EQ(error_of(with(k_base, "[WARP]\nThreads=2\n", "[WARP]\n")), "[WARP] line 14 | Threads is missing from the section");
  EXPECT_EQ(error_of(with(k_base, "[THREADING]\n1=1", "[THREADING]\n1=one")),
            "[THREADING] line 19 | expected a list of whole numbers, got 'one'");
  EXPECT_EQ(error_of(with(k_base, "[THREADING]\n1=1", "[THREADING]\n3=1")),
            "[THREADING] line 19 | entry 3 is outside 1..2 ([WARP] Threads=2)");
  EXPECT_EQ(error_of(k_base.substr(0, k_base.find("[TREADLING]"))),
            "[CONTENTS] line 10 | says the file has [TREADLING], but it does not (a truncated file?)");
  EXPECT_EQ(error_of(with(k_base, "[WARP]\nThreads=2", "[WARP]\nThreads=2\nColor=4")),
            "[WARP] line 16 | colour index 4 is not in the [COLOR TABLE] (the file has none)");
  EXPECT_EQ(error_of(with(k_base, "[TREADLING]\n1=1\n2=2\n", "[TREADLING]\n1=1\n2")),
            "[TREADLING] line 26 | expected KEY=VALUE, got '2' (a truncated or damaged file?)");
}

TEST(WifReader, SpecKeysBesideTheFileOverrideIt) {
  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() / "clothbake_wif_override_test";
  fs::create_directories(dir);
  const std::string t = with(with(k_base, "[WARP]\nThreads=2",
                                  "[COLOR TABLE]\n1=255,0,0\n2=0,255,0\n[WARP]\nThreads=2\nSpacing=0.1"),
                             "[WEFT]\nThreads=2", "[WEFT]\nThreads=2\n[WEFT COLORS]\n1=1\n2=2");
  std::ofstream(dir / "d.wif") << t;
  std::ofstream(dir / "plain.json") << R"({"weave": {"wif": "d.wif"}})";
  std::ofstream(dir / "over.json")
      << R"({"weave": {"wif": "d.wif"}, "warp": {"spacing_mm": 0.7, "colors": [[0, 0, 1]]},
            "weft": {"color": [0.5, 0.5, 0.5]}})";
  const ClothSpec a = load_cloth_spec((dir / "plain.json").string());
  EXPECT_FLOAT_EQ(a.warp.spacing_mm, 1.0f);
  EXPECT_EQ(a.weft.colors.size(), 2u);
  const ClothSpec b = load_cloth_spec((dir / "over.json").string());
  EXPECT_FLOAT_EQ(b.warp.spacing_mm, 0.7f);
  EXPECT_EQ(b.warp.colors, (std::vector<Imath::V3f>{{0, 0, 1}}));
  EXPECT_TRUE(b.weft.colors.empty());  // one colour for every pick replaces the file's
  EXPECT_EQ(b.weft.color, Imath::V3f(0.5f, 0.5f, 0.5f));
  EXPECT_EQ(b.draft, a.draft);
  // The shed from the spec: sinking turns this single-shaft draft inside out.
  std::ofstream(dir / "sink.json") << R"({"weave": {"wif": "d.wif", "rising_shed": false}})";
  const ClothSpec c = load_cloth_spec((dir / "sink.json").string());
  for (size_t p = 0; p < a.draft.size(); ++p)
    for (size_t e = 0; e < a.draft[p].size(); ++e) EXPECT_EQ(c.draft[p][e], 1 - a.draft[p][e]);
  // The file's errors name the file, not the spec.
  std::ofstream(dir / "bad.wif") << with(t, "[THREADING]\n1=1", "[THREADING]\n1=9");
  std::ofstream(dir / "bad.json") << R"({"weave": {"wif": "bad.wif"}})";
  try {
    (void)load_cloth_spec((dir / "bad.json").string());
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), (dir / "bad.wif").string());
  }
  fs::remove_all(dir);
}

}  // namespace
}  // namespace clothbake::io
