// Files that are not ours, through the real program: an output path that
// names a device, a FIFO, a socket or standard output is written to (or
// refused), never replaced by a regular file; a file an output replaces
// keeps its mode and group; the staging folders of killed runs are removed
// by the next run, and nothing else that looks like them; a side input (a
// seed image) on another grid is refused from its header before its data
// are decompressed, and a gzip stream is decompressed only as far as its
// header needs; a FIFO or a device named like an input is refused at once
// (docs/reliability.md, "Security").
#include <gtest/gtest.h>
#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/resource.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <sys/un.h>
#include <sys/wait.h>
#include <unistd.h>
#include <zlib.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <future>
#include <sstream>
#include <thread>

#include "small_inputs.hpp"

extern char** environ;

namespace stvd::testing {
namespace {

namespace fs = std::filesystem;

std::string contents(const std::string& file) {
  std::ifstream in(file, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

mode_t typeOf(const std::string& path) {
  struct stat status {};
  EXPECT_EQ(::lstat(path.c_str(), &status), 0) << path;
  return status.st_mode & S_IFMT;
}

bool isRoot() { return ::geteuid() == 0; }

/// CPU seconds and peak resident set (MiB) of the children waited for since
/// the last call: what one run of the tool cost.
struct ChildCost {
  double cpuSeconds = 0;
  double peakMiB = 0;
};
ChildCost childCostSince(const struct rusage& before) {
  struct rusage after {};
  ::getrusage(RUSAGE_CHILDREN, &after);
  auto seconds = [](const timeval& t) { return double(t.tv_sec) + 1e-6 * double(t.tv_usec); };
  return {seconds(after.ru_utime) + seconds(after.ru_stime) - seconds(before.ru_utime) - seconds(before.ru_stime),
          double(after.ru_maxrss) / 1024.0};
}

/// One gzip member holding `bytes` (gzip files may hold several, read one
/// after the other as one stream).
std::string gzipMember(const std::string& bytes) {
  z_stream z{};
  EXPECT_EQ(deflateInit2(&z, 9, Z_DEFLATED, 31, 9, Z_DEFAULT_STRATEGY), Z_OK);
  std::string out(deflateBound(&z, bytes.size()) + 64, '\0');
  z.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(bytes.data()));
  z.avail_in = static_cast<uInt>(bytes.size());
  z.next_out = reinterpret_cast<Bytef*>(out.data());
  z.avail_out = static_cast<uInt>(out.size());
  EXPECT_EQ(deflate(&z, Z_FINISH), Z_STREAM_END);
  out.resize(z.total_out);
  deflateEnd(&z);
  return out;
}

/// A NIfTI-1 header (352 bytes with the empty extension field) of a uint8
/// image of nx x ny x nz voxels of 1 mm, sform the identity.
std::string uint8NiftiHeader(int nx, int ny, int nz) {
  std::string h(352, '\0');
  auto put = [&h](std::size_t at, const auto& value) { std::memcpy(&h[at], &value, sizeof value); };
  put(0, std::int32_t{348});
  const std::int16_t dim[8] = {3, std::int16_t(nx), std::int16_t(ny), std::int16_t(nz), 1, 1, 1, 1};
  std::memcpy(&h[40], dim, sizeof dim);
  put(70, std::int16_t{2});  // DT_UINT8
  put(72, std::int16_t{8});
  const float pixdim[8] = {1, 1, 1, 1, 1, 1, 1, 1};
  std::memcpy(&h[76], pixdim, sizeof pixdim);
  put(108, 352.f);  // vox_offset
  put(112, 1.f);    // scl_slope
  put(254, std::int16_t{1});  // sform_code
  const float srow[12] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0};
  std::memcpy(&h[280], srow, sizeof srow);
  std::memcpy(&h[344], "n+1\0", 4);
  return h;
}

// --- Outputs that are streams ------------------------------------------------

class ToolStreamOutputs : public SmallInputsTest {};

TEST_F(ToolStreamOutputs, AFifoOutputIsWrittenToAndStaysAFifo) {
  ASSERT_EQ(::mkfifo(out("stats.fifo").c_str(), 0644), 0);
  // The reader: opens the FIFO (waiting for the writer) and reads it all.
  std::future<std::string> reader = std::async(std::launch::async, [this] { return contents(out("stats.fifo")); });
  const ToolRun run = runToolInBash("timeout 60 \"$0\" \"$@\"", distanceRun(out("d.nii.gz"), out("stats.fifo")));
  if (run.exitCode != 0) {  // let the reader go
    const int fd = ::open(out("stats.fifo").c_str(), O_WRONLY | O_NONBLOCK);
    if (fd >= 0) ::close(fd);
  }
  const std::string streamed = reader.get();
  ASSERT_EQ(run.exitCode, 0) << run.err;
  EXPECT_EQ(typeOf(out("stats.fifo")), S_IFIFO);
  EXPECT_NE(streamed.find("\"command\": \"distance\""), std::string::npos) << streamed.substr(0, 200);
  EXPECT_TRUE(fs::is_regular_file(out("d.nii.gz")));
  EXPECT_EQ(listFolder(path("out")), (std::vector<std::string>{"d.nii.gz", "stats.fifo"}));
}

TEST_F(ToolStreamOutputs, AnOutputThatLeadsToStandardOutputIsWrittenThere) {
  // What -o /dev/stdout is, without touching the machine's /dev: a link to
  // this process's descriptor 1 (the file that captures stdout).
  fs::create_symlink("/proc/self/fd/1", out("table"));
  const ToolRun run = runTool(connectivityRun(out("table")));
  ASSERT_EQ(run.exitCode, 0) << run.err;
  EXPECT_EQ(typeOf(out("table")), S_IFLNK);
  EXPECT_EQ(run.out.rfind("region_a\tregion_b\tgeodesic_mm", 0), 0u) << run.out;
  EXPECT_EQ(listFolder(path("out")), std::vector<std::string>{"table"});
}

TEST_F(ToolStreamOutputs, ACharacterDeviceOutputIsWrittenToNotReplaced) {
  if (!isRoot()) GTEST_SKIP() << "making a device node needs root (CI runs as root)";
  ASSERT_EQ(::mknod(out("null").c_str(), S_IFCHR | 0666, makedev(1, 3)), 0);  // what /dev/null is
  const ToolRun run = runTool(distanceRun(out("d.nii.gz"), out("null")));
  ASSERT_EQ(run.exitCode, 0) << run.err;
  EXPECT_EQ(typeOf(out("null")), S_IFCHR);
  EXPECT_EQ(listFolder(path("out")), (std::vector<std::string>{"d.nii.gz", "null"}));
}

TEST_F(ToolStreamOutputs, AStreamThatCannotBeWrittenTakesTheRunsFilesWithIt) {
  if (!isRoot()) GTEST_SKIP() << "making a device node needs root (CI runs as root)";
  ASSERT_EQ(::mknod(out("full").c_str(), S_IFCHR | 0666, makedev(1, 7)), 0);  // /dev/full: every write fails
  const ToolRun run = runTool(distanceRun(out("d.nii.gz"), out("full")));
  EXPECT_EQ(run.exitCode, 5);
  EXPECT_NE(run.err.find(out("full") + ": cannot write to a character device: No space left on device"),
            std::string::npos)
      << run.err;
  EXPECT_EQ(std::count(run.err.begin(), run.err.end(), '\n'), 1) << run.err;
  EXPECT_EQ(typeOf(out("full")), S_IFCHR);
  EXPECT_EQ(listFolder(path("out")), std::vector<std::string>{"full"});  // no map without its statistics
}

TEST_F(ToolStreamOutputs, ASocketIsRefusedAndLeftAsItIs) {
  // In a folder of a short name: a socket's path has at most 107 bytes.
  char folder[] = "/tmp/stvd-socket-XXXXXX";
  ASSERT_NE(::mkdtemp(folder), nullptr);
  struct Remove {
    std::string f;
    ~Remove() { fs::remove_all(f); }
  } remove{folder};
  const int s = ::socket(AF_UNIX, SOCK_STREAM, 0);
  ASSERT_GE(s, 0);
  sockaddr_un address{};
  address.sun_family = AF_UNIX;
  const std::string where = std::string(folder) + "/s.json";
  ASSERT_LT(where.size(), sizeof address.sun_path);
  std::strcpy(address.sun_path, where.c_str());
  ASSERT_EQ(::bind(s, reinterpret_cast<sockaddr*>(&address), sizeof address), 0);
  const ToolRun run = runTool(distanceRun(out("d.nii.gz"), where));
  ::close(s);
  EXPECT_EQ(run.exitCode, 5);
  EXPECT_NE(run.err.find(where + ": is a socket"), std::string::npos) << run.err;
  EXPECT_EQ(typeOf(where), S_IFSOCK);
  EXPECT_EQ(listFolder(folder), std::vector<std::string>{"s.json"});
  EXPECT_TRUE(listFolder(path("out")).empty());
}

// --- Replaced files and leftovers ---------------------------------------------

class ToolReplacedOutputs : public SmallInputsTest {};

TEST_F(ToolReplacedOutputs, AReplacedOutputKeepsItsModeAndGroup) {
  ASSERT_EQ(runTool(distanceRun(out("d.nii.gz"), out("d.json"))).exitCode, 0);
  ASSERT_EQ(::chmod(out("d.nii.gz").c_str(), 0600), 0);
  ASSERT_EQ(::chmod(out("d.json").c_str(), 0640), 0);
  const gid_t group = isRoot() ? 4242 : ::getegid();  // root may give any group
  ASSERT_EQ(::chown(out("d.json").c_str(), static_cast<uid_t>(-1), group), 0);
  ASSERT_EQ(runTool(distanceRun(out("d.nii.gz"), out("d.json"))).exitCode, 0);
  struct stat map {}, stats {};
  ASSERT_EQ(::stat(out("d.nii.gz").c_str(), &map), 0);
  ASSERT_EQ(::stat(out("d.json").c_str(), &stats), 0);
  EXPECT_EQ(map.st_mode & 07777, 0600u);
  EXPECT_EQ(stats.st_mode & 07777, 0640u);
  EXPECT_EQ(stats.st_gid, group);
}

TEST_F(ToolReplacedOutputs, StagingFoldersOfAKilledRunAreRemovedByTheNextAndNothingElse) {
  const std::string brain = sampleFile("dti_tensor_dipy5d.nii.gz");
  const std::vector<std::string> arguments{"distance", brain, "--seed-voxel", "55,54,15", "-o", out("d.nii.gz"),
                                           "--stats", out("d.json"), "-q"};
  // A folder named like a staging folder that a run of ours did not make,
  // holding someone's file.
  fs::create_directory(out(".stvd-staging-1-1"));
  std::ofstream(out(".stvd-staging-1-1/notes.txt")) << "not stvd's";
  // A run killed (SIGKILL, as the OOM killer does) while it writes.
  std::string leftover;
  for (int attempt = 0; attempt < 5 && leftover.empty(); ++attempt) {
    std::vector<std::string> words{toolExecutable()};
    words.insert(words.end(), arguments.begin(), arguments.end());
    std::vector<char*> argv;
    for (std::string& w : words) argv.push_back(w.data());
    argv.push_back(nullptr);
    pid_t pid = -1;
    ASSERT_EQ(::posix_spawn(&pid, argv[0], nullptr, nullptr, argv.data(), environ), 0);
    const std::string prefix = ".stvd-staging-" + std::to_string(pid) + "-";
    auto staged = [&]() -> std::string {
      std::error_code ec;
      for (const auto& entry : fs::directory_iterator(path("out"), ec)) {
        const std::string name = entry.path().filename().string();
        std::error_code inner;
        if (name.rfind(prefix, 0) == 0 && fs::exists(entry.path() / "d.nii.gz", inner)) return entry.path().string();
      }
      return "";
    };
    std::string found;
    while (found.empty() && ::waitpid(pid, nullptr, WNOHANG) == 0) found = staged();
    ::kill(pid, SIGKILL);
    ::waitpid(pid, nullptr, 0);
    if (!found.empty() && fs::exists(found)) leftover = found;
    std::error_code ec;
    fs::remove(out("d.nii.gz"), ec);
    fs::remove(out("d.json"), ec);
  }
  ASSERT_FALSE(leftover.empty()) << "the run was never caught while writing";

  const ToolRun run = runTool(arguments);
  ASSERT_EQ(run.exitCode, 0) << run.err;
  EXPECT_FALSE(fs::exists(leftover)) << leftover << " is still there";
  EXPECT_EQ(contents(out(".stvd-staging-1-1/notes.txt")), "not stvd's");
  EXPECT_EQ(listFolder(path("out")), (std::vector<std::string>{".stvd-staging-1-1", "d.json", "d.nii.gz"}));
}

// --- Side inputs --------------------------------------------------------------

class ToolSideInputs : public SmallInputsTest {};

TEST_F(ToolSideInputs, ASideImageOnAHugeGridIsRefusedFromItsHeader) {
  // 800^3 voxels of zeros in half a megabyte: the header and then 500
  // gzip members of 1,024,000 zero bytes each.
  const std::string bomb = in("huge.nii.gz");
  {
    std::ofstream file(bomb, std::ios::binary);
    file << gzipMember(uint8NiftiHeader(800, 800, 800));
    const std::string zeros = gzipMember(std::string(1024000, '\0'));
    for (int m = 0; m < 500; ++m) file << zeros;
  }
  ASSERT_LT(fs::file_size(bomb), 1u << 20);
  // As seed labels, a mask, a label image and target labels.
  std::vector<std::string> seeds = distanceRun(out("d.nii.gz"));
  seeds.erase(seeds.begin() + 4, seeds.begin() + 6);  // no --seed-voxel
  seeds.insert(seeds.end(), {"--seeds", bomb});
  std::vector<std::string> mask = distanceRun(out("d.nii.gz"));
  mask[7] = bomb;  // --mask FILE
  std::vector<std::string> labels = connectivityRun(out("c.tsv"));
  labels[5] = bomb;  // --labels FILE
  std::vector<std::string> targets = pathRun(out("p.trk"), out("p.tsv"));
  targets[7] = bomb;  // --targets FILE
  const std::vector<std::pair<std::vector<std::string>, std::string>> cases{
      {seeds, "the seed labels are"}, {mask, "the mask is"}, {labels, "the labels are"},
      {targets, "the target labels are"}};
  for (const auto& [arguments, subject] : cases) {
    struct rusage before {};
    ::getrusage(RUSAGE_CHILDREN, &before);
    const ToolRun run = runTool(arguments);
    const ChildCost cost = childCostSince(before);
    EXPECT_EQ(run.exitCode, 3) << run.err;
    EXPECT_NE(run.err.find(bomb + ": " + subject + " on another grid than " + in("t.nii") +
                           " (size 800x800x800 differs from 11x9x7)"),
              std::string::npos)
        << run.err;
    // Read in full, the image took 3 GB and 15 to 50 s of CPU time.
    EXPECT_LT(cost.peakMiB, 1024.0) << subject;
    EXPECT_LT(cost.cpuSeconds, 2.0) << subject;
  }
  EXPECT_TRUE(listFolder(path("out")).empty());
}

TEST_F(ToolSideInputs, GzipDataAreDecompressedOnlyAsFarAsTheHeaderNeeds) {
  // The seed labels of the small inputs, compressed, followed by 4 GiB of
  // zeros in 256 more gzip members (4 MB on disk).
  {
    std::ofstream seeds(in("labels.nii.gz"), std::ios::binary);
    seeds << gzipMember(contents(in("labels.nii")));
    const std::string zeros = gzipMember(std::string(16u << 20, '\0'));
    for (int m = 0; m < 256; ++m) seeds << zeros;
  }
  std::vector<std::string> arguments = distanceRun(out("d.nii.gz"));
  arguments.erase(arguments.begin() + 4, arguments.begin() + 6);
  arguments.insert(arguments.end(), {"--seeds", in("labels.nii.gz")});
  struct rusage before {};
  ::getrusage(RUSAGE_CHILDREN, &before);
  const ToolRun run = runTool(arguments);
  const ChildCost cost = childCostSince(before);
  ASSERT_EQ(run.exitCode, 0) << run.err;
  // Counting the whole stream took 2.7 s of CPU time per GiB.
  EXPECT_LT(cost.cpuSeconds, 3.0);
  EXPECT_TRUE(fs::is_regular_file(out("d.nii.gz")));
}

TEST_F(ToolSideInputs, AFifoOrADeviceNamedLikeAnInputIsRefusedAtOnce) {
  // Each would block the reader (a FIFO nobody writes) or never end
  // (/dev/zero); every reader of the tool refuses them at once. A link is
  // made to /dev/zero rather than a device node, which needs root.
  ASSERT_EQ(::mkfifo(in("mask.fifo.nii").c_str(), 0644), 0);
  ASSERT_EQ(::mkfifo(in("seeds.nhdr").c_str(), 0644), 0);
  ASSERT_EQ(::mkfifo(in("mesh.off").c_str(), 0644), 0);
  fs::create_symlink("/dev/zero", in("zero.nii"));
  fs::create_symlink("/dev/zero", in("zero.ply"));
  fs::create_symlink("/dev/zero", in("zero.node"));
  std::ofstream(in("zero.ele")) << "0 4 0\n";
  struct Case {
    std::vector<std::string> arguments;
    std::string file;
  };
  std::vector<std::string> withMask = distanceRun(out("d.nii.gz"));
  withMask[withMask.size() - 4] = in("mask.fifo.nii");  // --mask FILE
  std::vector<std::string> withSeeds = distanceRun(out("d.nii.gz"));
  withSeeds.insert(withSeeds.end(), {"--seeds", in("seeds.nhdr")});
  std::vector<Case> cases{
      {withMask, in("mask.fifo.nii")},
      {withSeeds, in("seeds.nhdr")},
      {{"distance", in("zero.nii"), "--seed-voxel", "1,1,1", "-o", out("d.nii.gz")}, in("zero.nii")},
      {{"distance", in("mesh.off"), "--seed-vertex", "0", "-o", out("d.ply")}, in("mesh.off")},
      {{"distance", in("zero.ply"), "--seed-vertex", "0", "-o", out("d.ply")}, in("zero.ply")},
      {{"distance", in("zero.node"), "--seed-vertex", "1", "-o", out("d.vtk")}, in("zero.node")},
  };
  if (withTetrahedralize()) cases.push_back({{"tetrahedralize", in("mesh.off"), "-o", out("m")}, in("mesh.off")});
  for (const Case& c : cases) {
    const ToolRun run = runToolInBash("timeout 20 \"$0\" \"$@\"", c.arguments);
    EXPECT_EQ(run.exitCode, 3) << c.file << ": " << run.err;
    EXPECT_NE(run.err.find(c.file), std::string::npos) << run.err;
    EXPECT_TRUE(run.err.find("not a regular file") != std::string::npos ||
                run.err.find("is a FIFO") != std::string::npos || run.err.find("a character device") != std::string::npos)
        << run.err;
    EXPECT_EQ(std::count(run.err.begin(), run.err.end(), '\n'), 1) << run.err;
  }
  EXPECT_TRUE(listFolder(path("out")).empty());
}

}  // namespace
}  // namespace stvd::testing
