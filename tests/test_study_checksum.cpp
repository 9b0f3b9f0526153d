// Checksummed run files (issue 18): every results file begins with a user block holding the XXH3-64
// of every byte after it (apps/h5out.hpp: checksum_block); HDF5 and h5py read the file as before.
// verify_checksum tells intact, absent (older files) and failed apart, and a study that resumes
// verifies each run file before it trusts it. The flip campaign: one byte flipped in each of 256 run
// files, at positions spread over the whole file (the checksum block included); on resume every
// flipped run is made again, none is used, and the study ends as an uninterrupted one.
#include <catch2/catch.hpp>
#include <hdf5.h>
#include <sys/stat.h>

#include <fstream>
#include <iostream>
#include <string>
#include <vector>

#include "apps/h5in.hpp"
#include "apps/h5out.hpp"
#include "h5content.hpp"
#include "process.hpp"
#include "scenes.hpp"
#include "study_fixtures.hpp"

namespace fs = std::filesystem;
using namespace slipfront;
using namespace slipfront::testing;

namespace {

const std::string bin = SLIPFRONT_BINARY;


std::string read_bytes(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}
void write_bytes(const fs::path& p, const std::string& bytes) { std::ofstream(p, std::ios::binary) << bytes; }

// A small results file written by write_results (both models of the imposed-rate scene).
fs::path write_small_results(const fs::path& dir) {
  compare::Scene scene = imposed_rate_scene();
  compare::ModelResult r;
  r.model = "continuum";
  r.x = {0.0};
  r.series["t"] = {0.0, 0.5, 1.0};
  r.series["sigma"] = {1.0, 0.9, 0.8};
  r.events.t_star = 0.25;
  const fs::path file = dir / "results.h5";
  app::write_results(file, scene, "scene = \"imposed\"\n", {r}, app::RunMeta{});
  return file;
}

long long inode_and_mtime(const fs::path& p) {
  struct stat st {};
  REQUIRE(::stat(p.c_str(), &st) == 0);
  return static_cast<long long>(st.st_ino) * 1000000007LL + st.st_mtim.tv_nsec + st.st_mtim.tv_sec * 1000000000LL;
}

}  // namespace

TEST_CASE("checksum: results files begin with the checksum of the rest, and stay HDF5 files", "[study][checksum]") {
  const TempDir dir("checksum-file");
  const fs::path file = write_small_results(dir.path);
  const std::string bytes = read_bytes(file);
  REQUIRE(bytes.size() > app::checksum_block_bytes);
  CHECK(bytes.substr(0, app::checksum_magic.size()) == app::checksum_magic);
  CHECK(bytes.substr(0, app::checksum_block_bytes) == app::checksum_block(std::string_view(bytes).substr(512)));
  CHECK(bytes.substr(512, 8) == "\x89HDF\r\n\x1a\n");  // HDF5's superblock right after the block
  CHECK(app::verify_checksum(file).state == app::Checksum::intact);
  // HDF5 reads it (and reports the user block), and so does h5in
  {
    const hid_t f = H5Fopen(file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
    REQUIRE(f >= 0);
    const hid_t fcpl = H5Fget_create_plist(f);
    hsize_t ub = 0;
    H5Pget_userblock(fcpl, &ub);
    CHECK(ub == 512);
    H5Pclose(fcpl);
    H5Fclose(f);
  }
  const app::ResultsFile back = app::read_results(file, {.verified = true});
  REQUIRE(back.models.size() == 1);
  CHECK(back.models[0].series.at("sigma") == std::vector<double>{1.0, 0.9, 0.8});
  // h5py, when it is installed: the user block is skipped
  const std::string python = fs::exists("/usr/bin/python3") ? "/usr/bin/python3" : find_program("python3");
  if (!python.empty() && run({python, "-c", "import h5py"}, dir.path).code == 0) {
    const Output py = run({python, "-c",
                           "import h5py; f = h5py.File('results.h5', 'r'); "
                           "print(f.userblock_size, list(f['continuum/series/sigma'][:]), f['meta'].attrs['status'])"},
                          dir.path);
    INFO(py.err);
    CHECK(py.code == 0);
    CHECK(contains(py.out, "512 [1.0, 0.9, 0.8] complete"));
  } else {
    WARN("h5py is not installed: its reading of the user block is not checked here");
  }
}

TEST_CASE("checksum: verify_checksum tells intact, absent and failed apart", "[study][checksum]") {
  const TempDir dir("checksum-states");
  const fs::path file = write_small_results(dir.path);
  const std::string good = read_bytes(file);
  struct Case {
    const char* what;
    std::string bytes;
    app::Checksum state;
    std::string detail;
  };
  std::string flipped = good, padding = good, truncated = good.substr(0, good.size() - 1), appended = good + "x";
  flipped[good.size() / 2] ^= 0x01;
  padding[300] = 'x';  // inside the block, after its text
  const std::vector<Case> cases = {
      {"intact", good, app::Checksum::intact, ""},
      {"one bit flipped in the HDF5 part", flipped, app::Checksum::failed, "checksum fails: stored xxh3-64 "},
      {"the block's zero padding changed", padding, app::Checksum::failed, "checksum block altered"},
      {"last byte cut", truncated, app::Checksum::failed, "(stored size " + std::to_string(good.size() - 512) + ")"},
      {"a byte appended", appended, app::Checksum::failed, "checksum fails"},
      {"shorter than the block", good.substr(0, 100), app::Checksum::failed, "truncated: 100 bytes"},
      {"an HDF5 file without block", good.substr(512), app::Checksum::absent, "no checksum"},
      {"the first byte of the block flipped", std::string(1, static_cast<char>(good[0] ^ 0x04)) + good.substr(1),
       app::Checksum::failed, "damaged: the file begins neither with slipfront's checksum block nor with HDF5's"},
      {"empty", "", app::Checksum::failed, "damaged"},
  };
  for (const Case& c : cases) {
    INFO(c.what);
    write_bytes(dir.path / "x.h5", c.bytes);
    const app::ChecksumCheck r = app::verify_checksum(dir.path / "x.h5");
    INFO(r.detail);
    CHECK(r.state == c.state);
    CHECK(contains(r.detail, c.detail));
    if (c.state != app::Checksum::intact)
      CHECK_THROWS_AS(app::read_results(dir.path / "x.h5", {.verified = true}), app::InputError);
  }
  // not a regular file: an InputError, never a blocking read
  CHECK_THROWS_AS(app::verify_checksum("/dev/zero"), app::InputError);
  CHECK_THROWS_AS(app::verify_checksum(dir.path), app::InputError);
  CHECK_THROWS_AS(app::verify_checksum(dir.path / "absent.h5"), app::InputError);
}

TEST_CASE("checksum: flip campaign: one byte flipped in each of 256 run files, every one redone on resume, none used",
          "[study][checksum][resume]") {
  const TempDir dir("checksum-flips");
  write_sweep_study(dir.path);  // sweep.toml: imposed-rate sweep, both models, a few ms a run
  constexpr int n = 256;
  write_text(dir.path / "flips.toml", "study = \"flips\"\nkind = \"runs\"\nscene = \"sweep.toml\"\nseeds = " +
                                          std::to_string(n) + "\n");
  const std::vector<std::string> cmd = {bin, "study", "flips.toml", "--out", "s", "-j", "2"};
  const Output first = run(cmd, dir.path);
  INFO(first.err);
  REQUIRE(first.code == 0);
  const std::vector<fs::path> files = run_files(dir.path / "s");
  REQUIRE(files.size() == static_cast<std::size_t>(n));
  fs::copy(dir.path / "s", dir.path / "reference", fs::copy_options::recursive);

  // run k: its byte at k/n of the file (0 .. the last byte; the first 2 in the checksum block, one bit each)
  std::vector<std::size_t> positions;
  std::size_t size = 0;
  std::vector<long long> stamps;
  int detected = 0;
  for (int k = 0; k < n; ++k) {
    std::string bytes = read_bytes(files[k]);
    size = bytes.size();
    const std::size_t at = static_cast<std::size_t>(k) * (bytes.size() - 1) / (n - 1);
    bytes[at] = static_cast<char>(bytes[at] ^ (1 << (k % 8)));
    write_bytes(files[k], bytes);
    positions.push_back(at);
    stamps.push_back(inode_and_mtime(files[k]));
    detected += app::verify_checksum(files[k]).state == app::Checksum::failed;
  }
  CHECK(detected == n);
  CHECK(positions.front() == 0);
  CHECK(positions.back() == size - 1);
  const auto in_block = std::count_if(positions.begin(), positions.end(), [](std::size_t p) { return p < 512; });
  CHECK(in_block >= 2);

  const Output resumed = run(cmd, dir.path);
  INFO(resumed.err);
  REQUIRE(resumed.code == 0);
  // every flipped run made again, none skipped (none trusted), each named on stderr and in study.h5
  CHECK(contains(resumed.out, "runs: " + std::to_string(n) + " run now, 0 skipped (complete from an earlier "
                                                              "invocation), " + std::to_string(n) +
                                  " made again because their file failed its checksum"));
  CHECK(contains(resumed.err, "slipfront: note: " + std::to_string(n) + " run files are not trusted"));
  CHECK(contains(resumed.err, "runs/0000/results.h5: damaged"));           // its first byte
  CHECK(contains(resumed.err, "runs/0001/results.h5: checksum block altered"));  // the block's padding
  const H5Content study = read_h5(dir.path / "s" / "study.h5");
  const std::string untrusted = study.strings.at("/study/runs@untrusted");
  CHECK(std::count(untrusted.begin(), untrusted.end(), '\n') == n);
  CHECK(contains(untrusted, "runs/0005/results.h5: checksum fails: stored xxh3-64 "));  // the HDF5 part
  CHECK(study.numbers.at("/study/runs@skipped") == 0.0);
  CHECK(study.numbers.at("/study/runs@computed") == static_cast<double>(n));
  int redone = 0, same = 0;
  const std::vector<fs::path> reference = run_files(dir.path / "reference");
  for (int k = 0; k < n; ++k) {
    INFO(files[k].string() << " flipped at byte " << positions[k]);
    redone += inode_and_mtime(files[k]) != stamps[k];
    CHECK(app::verify_checksum(files[k]).state == app::Checksum::intact);
    const auto d = run_file_differences(reference[k], files[k]);
    same += d.empty();
    CHECK(d.empty());
  }
  CHECK(redone == n);
  CHECK(same == n);
  CHECK(study_differences(dir.path / "reference" / "study.h5", dir.path / "s" / "study.h5").empty());
  std::cout << "checksum flip campaign: " << n << " single-byte flips at positions 0 .. " << size - 1 << " of " << size
            << "-byte run files (" << in_block << " in the checksum block): " << detected << " detected by verify_checksum, "
            << redone << " runs made again on resume, " << n - redone << " used\n";

  // and a resume of the intact study trusts every file again
  const Output again = run(cmd, dir.path);
  REQUIRE(again.code == 0);
  CHECK(contains(again.out, "runs: 0 run now, " + std::to_string(n) + " skipped"));
}
