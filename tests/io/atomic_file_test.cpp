// io/atomic_file: outputs appear whole or not at all, and every unfinished
// one is known to the process until it is published.

#include "io/atomic_file.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <iterator>
#include <string>
#include <vector>

#include "core/error.h"

namespace clothbake::io {
namespace {

namespace fs = std::filesystem;

class AtomicFile : public ::testing::Test {
 protected:
  void SetUp() override {
    m_dir = fs::temp_directory_path() /
            ("clothbake_atomic_test_" +
             std::to_string(::testing::UnitTest::GetInstance()->random_seed()) + "_" +
             ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(m_dir);
    fs::create_directories(m_dir);
  }
  void TearDown() override { fs::remove_all(m_dir); }
  std::string path(const std::string& name) const { return (m_dir / name).string(); }
  static std::string bytes(const std::string& p) {
    std::ifstream in(p, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), {}};
  }
  static void put(const std::string& p, const std::string& text) {
    std::ofstream(p, std::ios::binary) << text;
  }
  /// Names in the folder other than `keep`.
  std::vector<std::string> others(std::initializer_list<std::string> keep) const {
    std::vector<std::string> out;
    for (const auto& e : fs::directory_iterator(m_dir)) {
      const std::string name = e.path().filename().string();
      if (std::find(keep.begin(), keep.end(), name) == keep.end()) out.push_back(name);
    }
    return out;
  }
  fs::path m_dir;
};

TEST_F(AtomicFile, AllFilesAppearTogetherOrNone) {
  put(path("a.exr"), "old a");
  put(path("a.png"), "old png");
  // The second file fails: the first must not replace its previous version.
  EXPECT_THROW(write_all_atomically({{path("a.exr"), [](const std::string& t) { put(t, "new a"); }},
                                     {path("a.png"),
                                      [&](const std::string& t) {
                                        put(t, "half");
                                        throw InputError("", "disk full", path("a.png"));
                                      }}}),
               InputError);
  EXPECT_EQ(bytes(path("a.exr")), "old a");
  EXPECT_EQ(bytes(path("a.png")), "old png");
  EXPECT_TRUE(others({"a.exr", "a.png"}).empty());

  write_all_atomically({{path("a.exr"), [](const std::string& t) { put(t, "new a"); }},
                        {path("a.png"), [](const std::string& t) { put(t, "new png"); }}});
  EXPECT_EQ(bytes(path("a.exr")), "new a");
  EXPECT_EQ(bytes(path("a.png")), "new png");
  EXPECT_TRUE(others({"a.exr", "a.png"}).empty());
}

TEST_F(AtomicFile, TemporaryKeepsFolderAndExtension) {
  const fs::path t(temporary_sibling(path("render.exr")));
  EXPECT_EQ(t.parent_path(), m_dir);
  EXPECT_EQ(t.extension(), ".exr");
  EXPECT_EQ(t.filename().string()[0], '.');
  EXPECT_NE(temporary_sibling(path("render.exr")), t.string());
}

TEST_F(AtomicFile, UnpublishedOutputIsRemoved) {
  const std::string temp = path("b.tmp-1");
  {
    UnfinishedOutput out(temp);
    fs::create_directories(temp);
    put(temp + "/x.exr", "x");
  }
  EXPECT_FALSE(fs::exists(temp));

  // Published: renamed away, nothing removed afterwards.
  {
    UnfinishedOutput out(temp);
    put(temp, "done");
    out.publish([&] { fs::rename(temp, path("b")); });
  }
  EXPECT_EQ(bytes(path("b")), "done");
  EXPECT_TRUE(others({"b"}).empty());
}

TEST_F(AtomicFile, OutputFolderIsCheckedFirst) {
  auto message = [](const std::string& p) {
    try {
      check_output_folder(p, "-o");
    } catch (const InputError& e) {
      return e.field() + " | " + e.message();
    }
    return std::string("(no error)");
  };
  EXPECT_EQ(message(path("r.exr")), "(no error)");
  EXPECT_EQ(message(path("missing/r.exr")),
            "-o | the folder " + path("missing") + " does not exist");
  put(path("file"), "");
  EXPECT_EQ(message(path("file/r.exr")), "-o | " + path("file") + " is not a folder");
  fs::create_directories(path("r2.exr"));
  EXPECT_EQ(message(path("r2.exr")), "-o | is a folder; expected a file name");
}

}  // namespace
}  // namespace clothbake::io
