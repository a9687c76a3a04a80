// io/atomic_file: outputs appear whole or not at all, and every unfinished
// one is known to the process until it is published.

#include "io/atomic_file.h"

#include <gtest/gtest.h>

#include <csignal>
#include <functional>

#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <iterator>
#include <string>
#include <vector>

#include "core/util/error.h"
#include "core/util/image.h"
#include "core/texture/volume_texture.h"
#include "io/image_io.h"
#include "io/vdb_writer.h"

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

namespace clothbake::io {
namespace {

// A full disk must be an error, not a short file. /dev/full fails every write
// with ENOSPC. OpenImageIO's PNG writer and OpenVDB's file writer report no
// such failure themselves (a file size limit once left 8 KiB files and exit
// status 0), which is why PNGs are written by write_bytes_checked and a VDB is
// read back.
TEST(FullDisk, WriteBytesCheckedReportsIt) {
  const char bytes[16] = {};
  try {
    write_bytes_checked("/dev/full", "out/final.bin", bytes, sizeof bytes);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(e.message().find("No space left on device"), std::string::npos) << e.message();
    EXPECT_NE(std::string(e.what()).find("out/final.bin"), std::string::npos) << e.what();
  }
}

// Runs `write` in a child process whose files may not grow past 4 KiB
// (RLIMIT_FSIZE, SIGXFSZ ignored: writes fail with EFBIG after the first
// 4 KiB, as on a full disk): true if it threw an InputError.
bool refuses_past_a_file_size_limit(const std::function<void()>& write) {
  const pid_t pid = ::fork();
  if (pid == 0) {
    std::signal(SIGXFSZ, SIG_IGN);
    const rlimit limit{4096, 4096};
    ::setrlimit(RLIMIT_FSIZE, &limit);
    try {
      write();
    } catch (const InputError&) {
      ::_exit(0);
    }
    ::_exit(1);
  }
  int status = 0;
  ::waitpid(pid, &status, 0);
  return WIFEXITED(status) && WEXITSTATUS(status) == 0;
}

TEST(FullDisk, PngAndVdbWritersReportIt) {
  const auto dir = std::filesystem::temp_directory_path() /
                   ("clothbake_full_disk_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  // Noise: a PNG of some 190 KB, far past the limit.
  Image image(256, 256, 3);
  uint64_t x = 1;
  for (float& v : image.pixels) v = float((x = x * 6364136223846793005ull + 1) >> 40) / 16777216.0f;
  const std::string png = (dir / "top.png").string();
  EXPECT_TRUE(refuses_past_a_file_size_limit([&] { write_png_to(png, png, image, true); }));
  VolumeTexture volume(32, 32, 8, Imath::V3f(1, 1, 0.5f));
  for (int k = 0; k < 8; ++k)
    for (int j = 0; j < 32; ++j)
      for (int i = 0; i < 32; ++i)
        volume.at(i, j, k).density = float((i * 7 + j * 3 + k) % 5) / 4.0f;
  const std::string vdb = (dir / "volume.vdb").string();
  EXPECT_TRUE(
      refuses_past_a_file_size_limit([&] { write_volume_vdb_to(vdb, vdb, volume, "test"); }));
  // Without the limit both write.
  write_png_to(png, png, image, true);
  write_volume_vdb_to(vdb, vdb, volume, "test");
  EXPECT_GT(std::filesystem::file_size(png), 4096u);
  EXPECT_GT(std::filesystem::file_size(vdb), 4096u);
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace clothbake::io
