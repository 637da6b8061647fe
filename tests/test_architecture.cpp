// The dependency rules of docs/architecture.md, checked on the headers as they are: the header-only core
// (every header of shader, math, microfacet, occlusion, bsdf, lut, reference and filter outside a runtime/
// folder) includes only the C++ standard library's computational headers, other core headers and the shaders'
// portable source (shaders/portable/*.h, which shader/ and math/sampling.h compile as C++), and each area
// includes only the areas the document allows. A header that breaks a rule fails with its name and line.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <regex>
#include <set>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;

const fs::path kInclude = fs::path(MSH_SOURCE_DIR) / "include" / "microshadow";

struct Include {
  fs::path file;
  int line;
  std::string target;  // what is between < > or " "
};

std::vector<Include> includes_of(const fs::path& f) {
  std::vector<Include> out;
  std::ifstream in(f);
  const std::regex re(R"(^\s*#\s*include\s*[<"]([^>"]+)[>"])");
  std::string s;
  for (int n = 1; std::getline(in, s); ++n) {
    std::smatch m;
    if (std::regex_search(s, m, re)) out.push_back({f, n, m[1]});
  }
  return out;
}

// "occlusion" for include/microshadow/occlusion/x.h; "occlusion/runtime" for its runtime folder.
std::string area_of(const fs::path& header) {
  const fs::path rel = fs::relative(header, kInclude);
  auto it = rel.begin();
  std::string area = it->string();
  if (++it != rel.end() && std::next(it) != rel.end() && it->string() == "runtime") area += "/runtime";
  return area;
}

const std::set<std::string> kCoreAreas = {"shader", "math", "microfacet", "occlusion",
                                          "bsdf",   "lut",  "reference",  "filter"};

// The standard headers a core header may use: computation, no I/O, no threads, no type erasure (<memory>:
// GTR shares its precomputed Λ table between copies).
const std::set<std::string> kCoreStd = {"algorithm", "array",    "cmath",   "complex",     "concepts",
                                        "cstddef",   "cstdint",  "cstring", "limits",      "memory",
                                        "numeric",   "optional", "string",  "string_view", "type_traits",
                                        "utility",   "vector",   "bit",     "span"};

// Which areas each area may include (docs/architecture.md, "Dependency rules"). runtime/ folders may also
// include io and the third-party libraries.
const std::map<std::string, std::set<std::string>> kAllowed = {
    {"shader", {}},
    {"math", {"shader"}},
    {"io", {}},
    {"microfacet", {"math"}},
    {"filter", {"math"}},
    {"occlusion", {"math", "microfacet"}},
    {"bsdf", {"math", "microfacet"}},
    {"lut", {"math", "microfacet", "occlusion"}},
    {"reference", {"math", "microfacet", "occlusion", "bsdf"}},
    {"render", {"math", "microfacet", "occlusion", "bsdf", "lut", "reference", "filter", "io"}},
    {"study", {"math", "microfacet", "occlusion", "bsdf", "lut", "reference", "filter", "io", "render"}},
};

bool is_core(const std::string& area) { return kCoreAreas.count(area) > 0; }

std::string base_area(const std::string& area) { return area.substr(0, area.find('/')); }

TEST(Architecture, HeadersFollowTheDependencyRules) {
  ASSERT_TRUE(fs::is_directory(kInclude)) << kInclude;
  int headers = 0;
  for (const auto& e : fs::recursive_directory_iterator(kInclude)) {
    if (!e.is_regular_file() || e.path().extension() != ".h") continue;
    if (e.path().parent_path() == kInclude) continue;  // the umbrella header of the core, if any
    ++headers;
    const std::string area = area_of(e.path());
    const std::string base = base_area(area);
    const bool runtime = area.find("/runtime") != std::string::npos;
    ASSERT_TRUE(kAllowed.count(base)) << e.path() << ": area '" << base << "' is not in docs/architecture.md";
    for (const Include& inc : includes_of(e.path())) {
      const std::string where =
          inc.file.string() + ":" + std::to_string(inc.line) + " includes " + inc.target;
      if (inc.target.rfind("microshadow/", 0) == 0) {
        const std::string to = area_of(kInclude / inc.target.substr(12));
        const std::string to_base = base_area(to);
        if (to_base == base) {
          // Within an area: the core never includes its own runtime folder.
          EXPECT_FALSE(!runtime && is_core(base) && to != area && to.find("/runtime") != std::string::npos)
              << where;
          continue;
        }
        const bool allowed = kAllowed.at(base).count(to_base) > 0 || (runtime && to_base == "io");
        EXPECT_TRUE(allowed) << where << " (" << base << " may not depend on " << to_base << ")";
        if (is_core(base) && !runtime) {
          EXPECT_TRUE(is_core(to_base) && to.find("/runtime") == std::string::npos)
              << where << " (the core may include only core headers)";
        }
      } else if (is_core(base) && !runtime) {
        EXPECT_TRUE(kCoreStd.count(inc.target) > 0 || inc.target.rfind("shaders/portable/", 0) == 0)
            << where << " (a core header uses only computational standard headers)";
      }
    }
  }
  EXPECT_GT(headers, 40);
}

// The classification the rules rest on.
TEST(Architecture, AreaOfAHeader) {
  EXPECT_EQ(area_of(kInclude / "lut" / "runtime" / "x.h"), "lut/runtime");
  EXPECT_EQ(area_of(kInclude / "lut" / "x.h"), "lut");
  EXPECT_EQ(area_of(kInclude / "bsdf" / "runtime" / "x.h"), "bsdf/runtime");
  EXPECT_TRUE(is_core("occlusion"));
  EXPECT_FALSE(is_core("render"));
}

// docs/architecture.md's "Data flow" names commands, functions and files; each must still exist, so the
// picture cannot drift from the code silently. Names come from `backticks` and the mermaid block's a::b
// tokens.
std::string read_all(const fs::path& f) {
  std::ifstream in(f, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// Every .h/.cpp under include/ and src/, concatenated (a few MB).
const std::string& all_sources() {
  static const std::string text = [] {
    std::string t;
    for (const char* dir : {"include", "src"})
      for (const auto& e : fs::recursive_directory_iterator(fs::path(MSH_SOURCE_DIR) / dir))
        if (e.is_regular_file() && (e.path().extension() == ".h" || e.path().extension() == ".cpp"))
          t += read_all(e.path()) + "\n";
    return t;
  }();
  return text;
}

bool names_something(const std::string& token, std::string& why) {
  const fs::path root(MSH_SOURCE_DIR);
  const std::string& src = all_sources();
  if (token.rfind("microshadow ", 0) == 0 || token.rfind("verify ", 0) == 0) {
    // A command: its last word is a subcommand name literal of the CLI.
    const std::string word = token.substr(token.find_last_of(' ') + 1);
    why = "no CLI subcommand \"" + word + "\"";
    return src.find("\"" + word + "\"") != std::string::npos;
  }
  if (token.find("::") != std::string::npos) {
    const std::string id = token.substr(token.rfind("::") + 2);
    why = "no declaration of '" + id + "' under include/ or src/";
    return std::regex_search(src, std::regex("\\b" + id + "\\b"));
  }
  if (token.rfind("test_", 0) == 0) {
    why = "no ctest named " + token;
    return read_all(root / "CMakeLists.txt").find("NAME " + token) != std::string::npos ||
           fs::exists(root / "tests" / (token + ".cpp"));
  }
  if (fs::exists(root / token)) return true;
  if (token.find('/') != std::string::npos) {
    std::string t = token;
    if (t.front() == '<') t = t.substr(1, t.size() - 2);
    why = "no file or folder " + t;
    return fs::exists(root / t) || fs::exists(root / "include" / "microshadow" / t) ||
           fs::exists(root / "include" / t);
  }
  // A bare name (a class, a generated file): it appears in the sources.
  why = "'" + token + "' appears nowhere under include/ or src/";
  return src.find(token) != std::string::npos;
}

TEST(Architecture, DataFlowPictureNamesWhatExists) {
  const std::string doc = read_all(fs::path(MSH_SOURCE_DIR) / "docs" / "architecture.md");
  const auto begin = doc.find("## Data flow");
  ASSERT_NE(begin, std::string::npos) << "docs/architecture.md has no '## Data flow' section";
  const std::string sec = doc.substr(begin, doc.find("\n## ", begin + 3) - begin);
  std::set<std::string> tokens;
  const std::regex tick("`([^`\\n]+)`"), qualified(R"(\b([a-z_]+::[A-Za-z_]+))");
  for (auto it = std::sregex_iterator(sec.begin(), sec.end(), tick); it != std::sregex_iterator(); ++it)
    tokens.insert((*it)[1]);
  for (auto it = std::sregex_iterator(sec.begin(), sec.end(), qualified); it != std::sregex_iterator(); ++it)
    tokens.insert((*it)[1]);
  tokens.erase("test_architecture");
  EXPECT_GT(tokens.size(), 20u);
  for (const std::string& t : tokens) {
    if (t.find(' ') != std::string::npos && t.rfind("microshadow ", 0) != 0 && t.rfind("verify ", 0) != 0)
      continue;  // prose in backticks
    std::string why;
    EXPECT_TRUE(names_something(t, why)) << "docs/architecture.md, Data flow: `" << t << "`: " << why;
  }
}

// A renamed function is caught: the check is not vacuous.
TEST(Architecture, DataFlowCheckRejectsUnknownNames) {
  std::string why;
  EXPECT_FALSE(names_something("render::no_such_function_xyz", why));
  EXPECT_FALSE(names_something("microshadow bake no-such-command-xyz", why));
  EXPECT_FALSE(names_something("scripts/no_such_script.py", why));
  EXPECT_TRUE(names_something("render::load_height_map", why));
  EXPECT_TRUE(names_something("microshadow gen-material", why));
}

}  // namespace
