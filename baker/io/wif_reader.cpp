#include "io/wif_reader.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <limits>

#include "core/util/error.h"
#include "core/weave/weave.h"
#include "io/text_file.h"

namespace clothbake::io {

namespace {

constexpr int k_max_shafts = 65536;  // a Jacquard liftplan may list a shaft per end

std::string trim(std::string_view s) {
  size_t a = 0, b = s.size();
  while (a < b && std::isspace(static_cast<unsigned char>(s[a]))) ++a;
  while (b > a && std::isspace(static_cast<unsigned char>(s[b - 1]))) --b;
  return std::string(s.substr(a, b - a));
}

// Upper case, runs of spaces as one: "Rising  shed" and "RISING SHED" are one key.
std::string normalise(std::string_view s) {
  std::string out;
  bool space = false;
  for (char c : trim(s)) {
    if (std::isspace(static_cast<unsigned char>(c))) {
      space = true;
      continue;
    }
    if (space && !out.empty()) out += ' ';
    space = false;
    out += char(std::toupper(static_cast<unsigned char>(c)));
  }
  return out;
}

struct Entry {
  std::string key;    // normalised
  std::string value;  // trimmed, comment removed
  int line = 0;
};

struct Section {
  std::string name;  // as written, for messages
  int line = 0;
  std::vector<Entry> entries;
  const Entry* find(const std::string& key) const {
    const Entry* hit = nullptr;  // the last one wins, as in any INI reader
    for (const Entry& e : entries)
      if (e.key == key) hit = &e;
    return hit;
  }
};

class WifText {
 public:
  WifText(const std::string& text, std::string path) : m_path(std::move(path)) {
    int current = -1;  // index: the list grows while we read
    int line_no = 0;
    size_t at = 0;
    while (at <= text.size()) {
      size_t end = text.find('\n', at);
      if (end == std::string::npos) end = text.size();
      std::string_view raw(text.data() + at, end - at);
      at = end + 1;
      ++line_no;
      if (const size_t semi = raw.find(';'); semi != std::string_view::npos)
        raw = raw.substr(0, semi);
      const std::string line = trim(raw);
      if (line.empty()) continue;
      if (line.front() == '[') {
        if (line.back() != ']')
          fail("line " + std::to_string(line_no),
               "a section header must end with ']', got '" + line + "'");
        const std::string name = normalise(line.substr(1, line.size() - 2));
        // A section given twice: its entries join the first (last key wins).
        auto it = std::find_if(m_sections.begin(), m_sections.end(),
                               [&](const Section& s) { return s.name == name; });
        if (it == m_sections.end()) {
          m_sections.push_back(Section{name, line_no, {}});
          current = int(m_sections.size()) - 1;
        } else {
          current = int(it - m_sections.begin());
        }
        continue;
      }
      const size_t eq = line.find('=');
      if (current < 0)
        fail("line " + std::to_string(line_no),
             "text before the first [SECTION]: '" + line.substr(0, 40) + "'");
      if (eq == std::string::npos)
        fail(where(m_sections[current], line_no),
             "expected KEY=VALUE, got '" + line.substr(0, 40) + "' (a truncated or damaged file?)");
      m_sections[current].entries.push_back(
          Entry{normalise(line.substr(0, eq)), trim(line.substr(eq + 1)), line_no});
    }
  }

  const Section* section(const std::string& name) const {
    for (const Section& s : m_sections)
      if (s.name == name) return &s;
    return nullptr;
  }
  const std::vector<Section>& sections() const { return m_sections; }
  const std::string& path() const { return m_path; }

  static std::string where(const Section& s, int line) {
    return "[" + s.name + "] line " + std::to_string(line);
  }
  [[noreturn]] void fail(const std::string& field, const std::string& message) const {
    throw InputError(field, message, m_path);
  }

 private:
  std::string m_path;
  std::vector<Section> m_sections;
};

// Numbers -------------------------------------------------------------------

long long to_integer(const WifText& f, const Section& s, const Entry& e, std::string_view text,
                     const char* what) {
  const std::string t = trim(text);
  long long v = 0;
  const auto [ptr, ec] = std::from_chars(t.data(), t.data() + t.size(), v);
  if (t.empty() || ec != std::errc() || ptr != t.data() + t.size())
    f.fail(WifText::where(s, e.line), std::string("expected ") + what + ", got '" +
                                          t.substr(0, 40) + "'");
  return v;
}

double to_real(const WifText& f, const Section& s, const Entry& e, std::string_view text,
               const char* what) {
  const std::string t = trim(text);
  double v = 0;
  const auto [ptr, ec] = std::from_chars(t.data(), t.data() + t.size(), v);
  if (t.empty() || ec != std::errc() || ptr != t.data() + t.size() || !std::isfinite(v))
    f.fail(WifText::where(s, e.line), std::string("expected ") + what + ", got '" +
                                          t.substr(0, 40) + "'");
  return v;
}

std::vector<std::string> split_commas(const std::string& value) {
  std::vector<std::string> items;
  size_t at = 0;
  while (true) {
    const size_t comma = value.find(',', at);
    items.push_back(trim(value.substr(at, comma == std::string::npos ? std::string::npos
                                                                       : comma - at)));
    if (comma == std::string::npos) break;
    at = comma + 1;
  }
  return items;
}

// A list of thread/shaft/treadle numbers; empty items and 0 mean nothing.
std::vector<int> to_list(const WifText& f, const Section& s, const Entry& e, int max,
                         const std::string& max_name) {
  std::vector<int> out;
  for (const std::string& item : split_commas(e.value)) {
    if (item.empty()) continue;
    const long long v = to_integer(f, s, e, item, "a list of whole numbers");
    if (v < 0) f.fail(WifText::where(s, e.line), "negative entry " + std::to_string(v));
    if (v == 0) continue;
    if (v > max)
      f.fail(WifText::where(s, e.line), "names " + std::to_string(v) + ", above " + max_name +
                                            "=" + std::to_string(max));
    out.push_back(int(v));
  }
  return out;
}

bool to_bool(const WifText& f, const Section& s, const Entry& e) {
  const std::string v = normalise(e.value);
  if (v == "YES" || v == "TRUE" || v == "1" || v == "ON") return true;
  if (v == "NO" || v == "FALSE" || v == "0" || v == "OFF") return false;
  f.fail(WifText::where(s, e.line),
         e.key + ": expected yes/no (true/false, 1/0, on/off), got '" + e.value + "'");
}

// The key of a numbered entry ("12=3,4": thread 12), in [1, count].
int entry_number(const WifText& f, const Section& s, const Entry& e, int count,
                 const std::string& count_name) {
  const long long n = to_integer(f, s, e, e.key, "a numbered entry N=...");
  if (n < 1 || n > count)
    f.fail(WifText::where(s, e.line), "entry " + std::to_string(n) + " is outside 1.." +
                                          std::to_string(count) + " (" + count_name + "=" +
                                          std::to_string(count) + ")");
  return int(n);
}

int required_count(const WifText& f, const char* section, const char* key, int max) {
  const Section* s = f.section(section);
  if (s == nullptr)
    f.fail(std::string("[") + section + "]",
           std::string("the section is missing; it gives ") + key);
  const Entry* e = s->find(normalise(key));
  if (e == nullptr)
    f.fail(WifText::where(*s, s->line), std::string(key) + " is missing from the section");
  const long long v = to_integer(f, *s, *e, e->value, "a whole number");
  if (v < 1 || v > max)
    f.fail(WifText::where(*s, e->line), std::string(key) + " must be in 1.." +
                                            std::to_string(max) + ", got " + std::to_string(v));
  return int(v);
}

// mm per unit of [WARP] / [WEFT] Units.
double unit_mm(const WifText& f, const Section& s) {
  const Entry* e = s.find("UNITS");
  if (e == nullptr) return 10.0;  // centimeters, the WIF 1.1 default
  const std::string u = normalise(e->value);
  if (u == "CENTIMETERS" || u == "CENTIMETRES" || u == "CM") return 10.0;
  if (u == "MILLIMETERS" || u == "MILLIMETRES" || u == "MM") return 1.0;
  if (u == "INCHES" || u == "INCH" || u == "IN") return 25.4;
  if (u == "DECIPOINTS") return 25.4 / 720.0;
  f.fail(WifText::where(s, e->line),
         "Units: expected centimeters, inches or decipoints, got '" + e->value + "'");
}

struct Palette {
  double lo = 0.0, hi = 255.0;
  std::map<int, Imath::V3f> linear;
};

Imath::V3f rgb_in_range(const WifText& f, const Section& s, const Entry& e,
                        const std::string& value, const Palette& p) {
  const auto items = split_commas(value);
  if (items.size() != 3)
    f.fail(WifText::where(s, e.line), "expected r,g,b, got '" + value.substr(0, 40) + "'");
  Imath::V3f v;
  for (int c = 0; c < 3; ++c) {
    const double x = to_real(f, s, e, items[c], "a number");
    if (x < p.lo || x > p.hi)
      f.fail(WifText::where(s, e.line),
             "colour value " + items[c] + " is outside the palette's Range " +
                 std::to_string(static_cast<long long>(p.lo)) + "," +
                 std::to_string(static_cast<long long>(p.hi)));
    v[c] = float(x);
  }
  return display_to_linear(v, float(p.lo), float(p.hi));
}

Palette read_palette(const WifText& f) {
  Palette p;
  if (const Section* s = f.section("COLOR PALETTE")) {
    if (const Entry* e = s->find("RANGE")) {
      const auto items = split_commas(e->value);
      if (items.size() != 2)
        f.fail(WifText::where(*s, e->line), "Range: expected lo,hi, got '" + e->value + "'");
      p.lo = to_real(f, *s, *e, items[0], "a number");
      p.hi = to_real(f, *s, *e, items[1], "a number");
      if (!(p.hi > p.lo))
        f.fail(WifText::where(*s, e->line), "Range: hi must exceed lo, got '" + e->value + "'");
    }
    if (const Entry* e = s->find("FORM"); e != nullptr && normalise(e->value) != "RGB")
      f.fail(WifText::where(*s, e->line), "Form: only RGB colours are supported, got '" +
                                              e->value + "'");
  }
  if (const Section* s = f.section("COLOR TABLE"))
    for (const Entry& e : s->entries) {
      const long long i = to_integer(f, *s, e, e.key, "a numbered entry N=r,g,b");
      if (i < 0 || i > k_max_shafts)
        f.fail(WifText::where(*s, e.line), "colour index " + std::to_string(i) + " out of range");
      p.linear[int(i)] = rgb_in_range(f, *s, e, e.value, p);
    }
  return p;
}

int palette_index(const WifText& f, const Section& s, const Entry& e, const std::string& value,
                  const Palette& p) {
  const long long i = to_integer(f, s, e, value, "a colour index");
  if (!p.linear.count(int(i)) || i < 0 || i > k_max_shafts)
    f.fail(WifText::where(s, e.line),
           "colour index " + std::to_string(i) + " is not in the [COLOR TABLE]" +
               (p.linear.empty() ? " (the file has none)" : ""));
  return int(i);
}

WifFamily read_family(const WifText& f, const char* name, int threads, const Palette& pal) {
  WifFamily fam;
  fam.threads = threads;
  const Section& s = *f.section(name);  // required_count checked it exists
  const double mm = unit_mm(f, s);
  if (const Entry* e = s.find("COLOR")) {
    // WIF 1.1: "1 or 4 integers", the palette index and optionally its RGB
    // (which readers are to ignore). Three numbers are read as an RGB.
    const auto items = split_commas(e->value);
    if (items.size() == 3)
      fam.color = rgb_in_range(f, s, *e, e->value, pal);
    else
      fam.color = pal.linear.at(palette_index(f, s, *e, items[0], pal));
  }
  auto positive_length = [&](const Section& sec, const Entry& e, const char* what) {
    const double v = to_real(f, sec, e, e.value, what);
    if (!(v > 0.0)) f.fail(WifText::where(sec, e.line), std::string(what) + " must be > 0");
    return float(v * mm);
  };
  if (const Entry* e = s.find("SPACING")) fam.spacing_mm = positive_length(s, *e, "a spacing");
  if (const Entry* e = s.find("THICKNESS"))
    fam.thickness_mm = positive_length(s, *e, "a thickness");

  const std::string family = name;
  const std::string count_name = "[" + family + "] Threads";
  if (const Section* c = f.section(family + " COLORS")) {
    fam.color_index.assign(threads, -1);
    for (const Entry& e : c->entries) {
      const int n = entry_number(f, *c, e, threads, count_name);
      // Some programs write "index,count"-free lists; only the first item is the colour.
      fam.color_index[n - 1] = palette_index(f, *c, e, split_commas(e.value)[0], pal);
    }
  }
  auto per_thread = [&](const char* suffix, std::vector<float>& out) {
    const Section* c = f.section(family + " " + suffix);
    if (c == nullptr) return;
    out.assign(threads, std::numeric_limits<float>::quiet_NaN());
    for (const Entry& e : c->entries) {
      const int n = entry_number(f, *c, e, threads, count_name);
      out[n - 1] = positive_length(*c, e, "a length");
    }
  };
  per_thread("SPACING", fam.spacings_mm);
  per_thread("THICKNESS", fam.thicknesses_mm);
  return fam;
}

}  // namespace

bool is_wif_path(const std::string& path) {
  if (path.size() < 4) return false;
  std::string ext = path.substr(path.size() - 4);
  for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
  return ext == ".wif";
}

// About 90 lines, kept whole: the sections in the order the drawdown needs
// them (counts, the loom, the shed, colours, sizes), each refusal beside the
// value it checks.
WifFile parse_wif(const std::string& text, const std::string& path) {
  const WifText f(text, path);
  WifFile wif;
  wif.path = path;
  if (const Section* s = f.section("WIF"))
    if (const Entry* e = s->find("SOURCE PROGRAM")) wif.source_program = e->value;

  // A section [CONTENTS] says is there but is not: the file was cut short.
  if (const Section* s = f.section("CONTENTS"))
    for (const Entry& e : s->entries)
      if (to_bool(f, *s, e) && f.section(e.key) == nullptr)
        f.fail(WifText::where(*s, e.line), "says the file has [" + e.key +
                                               "], but it does not (a truncated file?)");

  LoomDraft& d = wif.loom;
  d.ends = required_count(f, "WARP", "Threads", k_max_draft_threads);
  d.picks = required_count(f, "WEFT", "Threads", k_max_draft_threads);
  const Section* threading = f.section("THREADING");
  const Section* liftplan = f.section("LIFTPLAN");
  const Section* treadling = f.section("TREADLING");
  const Section* tieup = f.section("TIEUP");
  if (threading == nullptr)
    f.fail("[THREADING]", "the section is missing: without it no end is on a shaft");
  if (liftplan == nullptr && treadling == nullptr)
    f.fail("[TREADLING]", "the file has neither [TREADLING] nor [LIFTPLAN]: no pick lifts a shaft");
  d.shafts = required_count(f, "WEAVING", "Shafts", k_max_shafts);
  d.has_liftplan = liftplan != nullptr;
  if (const Entry* e = f.section("WEAVING")->find("RISING SHED"))
    d.rising_shed = to_bool(f, *f.section("WEAVING"), *e);

  const std::string shafts_name = "[WEAVING] Shafts";
  d.threading.assign(d.ends, {});
  for (const Entry& e : threading->entries)
    d.threading[entry_number(f, *threading, e, d.ends, "[WARP] Threads") - 1] =
        to_list(f, *threading, e, d.shafts, shafts_name);
  if (d.has_liftplan) {
    d.liftplan.assign(d.picks, {});
    for (const Entry& e : liftplan->entries)
      d.liftplan[entry_number(f, *liftplan, e, d.picks, "[WEFT] Threads") - 1] =
          to_list(f, *liftplan, e, d.shafts, shafts_name);
  } else {
    d.treadles = required_count(f, "WEAVING", "Treadles", k_max_shafts);
    d.treadling.assign(d.picks, {});
    for (const Entry& e : treadling->entries)
      d.treadling[entry_number(f, *treadling, e, d.picks, "[WEFT] Threads") - 1] =
          to_list(f, *treadling, e, d.treadles, "[WEAVING] Treadles");
    d.tieup.assign(d.treadles, {});
    // A tie-up row for a treadle above Treadles is one no pick can press:
    // Fiberworks PCW writes them (its tabby treadles), so they are skipped.
    if (tieup != nullptr)
      for (const Entry& e : tieup->entries) {
        const long long t = to_integer(f, *tieup, e, e.key, "a numbered entry N=...");
        if (t < 1)
          f.fail(WifText::where(*tieup, e.line), "entry " + std::to_string(t) + " is below 1");
        const std::vector<int> shafts = to_list(f, *tieup, e, d.shafts, shafts_name);
        if (t <= d.treadles) d.tieup[t - 1] = shafts;
      }
  }

  const Palette palette = read_palette(f);
  wif.palette = palette.linear;
  wif.warp = read_family(f, "WARP", d.ends, palette);
  wif.weft = read_family(f, "WEFT", d.picks, palette);
  return wif;
}

WifFile read_wif_file(const std::string& path) {
  return parse_wif(read_text_file(path, "a WIF file"), path);
}

ClothSpec apply_wif(const WifFile& wif, ClothSpec spec) {
  spec.draft = drawdown(wif.loom);
  spec.draft_source = wif.path;
  spec.draft_program = wif.source_program;
  auto family = [&](const WifFamily& fam, YarnSpec& y) {
    // The cross-section keeps the default's height-to-width ratio.
    const float aspect = y.thickness_mm / y.width_mm;
    const float width_per_spacing = y.width_mm / y.spacing_mm;
    if (fam.spacing_mm) {
      y.spacing_mm = *fam.spacing_mm;
      // A file that gives the spacing but not the thickness: the yarn scales
      // with the spacing, as clothbake's default fills 0.88 of it.
      y.width_mm = width_per_spacing * y.spacing_mm;
    }
    if (fam.thickness_mm) y.width_mm = *fam.thickness_mm;
    y.thickness_mm = aspect * y.width_mm;
    if (fam.color) y.color = *fam.color;
    y.colors.clear();
    if (!fam.color_index.empty()) {
      y.colors.resize(fam.threads);
      for (int i = 0; i < fam.threads; ++i)
        y.colors[i] = fam.color_index[i] < 0 ? y.color : wif.palette.at(fam.color_index[i]);
    }
    auto filled = [](const std::vector<float>& in, float fill) {
      std::vector<float> out(in);
      for (float& v : out)
        if (std::isnan(v)) v = fill;
      return out;
    };
    y.spacings_mm = filled(fam.spacings_mm, y.spacing_mm);
    y.widths_mm = filled(fam.thicknesses_mm, y.width_mm);
    if (!fam.thickness_mm && fam.thicknesses_mm.empty() && !y.spacings_mm.empty()) {
      // Spacing per thread but no thickness: each thread fills the same share
      // of the narrower gap beside it as clothbake's default yarn does.
      const size_t n = y.spacings_mm.size();
      y.widths_mm.resize(n);
      for (size_t i = 0; i < n; ++i)
        y.widths_mm[i] =
            width_per_spacing * std::min(y.spacings_mm[i], y.spacings_mm[(i + n - 1) % n]);
    }
  };
  family(wif.warp, spec.warp);
  family(wif.weft, spec.weft);
  return spec;
}

}  // namespace clothbake::io
