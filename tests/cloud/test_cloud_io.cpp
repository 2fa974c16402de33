// Point-cloud files: round trips through every writer, PCL's binary_compressed layout, KITTI
// frames, and one clear error for each kind of malformed file.
#include <gtest/gtest.h>

#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <cstring>
#include <filesystem>

#include "starnav/cloud/cloud_io.hpp"
#include "starnav/cloud/kitti_dataset.hpp"
#include "starnav/cloud/lidar_recording.hpp"
#include "starnav/core/error.hpp"
#include "support/test_support.hpp"

namespace starnav {
namespace {

const PointCloud kPoints = {{1.5, -2.25, 0.125}, {0, 0, 0}, {-3.5, 4.75, 10.0}};

std::string floats(const std::vector<float>& v) { return {reinterpret_cast<const char*>(v.data()), v.size() * 4}; }

// LZF with literal runs only (at most 32 bytes each): valid input for the decompressor.
std::string lzf_literals(const std::string& data) {
  std::string out;
  for (std::size_t i = 0; i < data.size(); i += 32) {
    const std::size_t n = std::min<std::size_t>(32, data.size() - i);
    out.push_back(static_cast<char>(n - 1));
    out += data.substr(i, n);
  }
  return out;
}

std::string error_field(const std::function<void()>& f) {
  try {
    f();
  } catch (const Error& e) {
    EXPECT_EQ(e.file(), "c.pcd") << e.what();
    return e.field();
  }
  ADD_FAILURE() << "no error";
  return {};
}

TEST(CloudIo, EveryWriterReadsBack) {
  for (auto format : {PointCloudFormat::Pcd, PointCloudFormat::Ply}) {
    for (auto enc : {PointCloudEncoding::Ascii, PointCloudEncoding::Binary}) {
      const std::string bytes = format_point_cloud(kPoints, format, enc);
      const PointCloudFile f = format == PointCloudFormat::Pcd ? parse_pcd(bytes, "x") : parse_ply(bytes, "x");
      ASSERT_EQ(f.points.size(), kPoints.size());
      for (std::size_t i = 0; i < kPoints.size(); ++i) EXPECT_LT((f.points[i] - kPoints[i]).norm(), 1e-6);
      EXPECT_EQ(format_point_cloud(kPoints, format, enc), bytes);  // same points, same bytes
    }
  }
  test::ScratchDir dir;
  const std::string path = (dir.path() / "c.pcd").string();
  write_point_cloud(path, kPoints, PointCloudFormat::Pcd, PointCloudEncoding::Binary);
  EXPECT_EQ(read_point_cloud(path).points.size(), 3u);
  EXPECT_THROW(write_point_cloud(path, PointCloud{{1e300, 0, 0}}, PointCloudFormat::Pcd), Error);
}

TEST(CloudIo, PcdWithExtraFieldsBinaryCompressedAndHoles) {
  // x y z intensity, the second point a NaN hole: records of 16 bytes.
  const std::string header = "VERSION 0.7\nFIELDS x y z intensity\nSIZE 4 4 4 4\nTYPE F F F F\nCOUNT 1 1 1 1\n"
                             "WIDTH 3\nHEIGHT 1\nPOINTS 3\n";
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const std::string binary = floats({1, 2, 3, 9, nan, nan, nan, 9, 4, 5, 6, 9});
  PointCloudFile f = parse_pcd(header + "DATA binary\n" + binary, "b.pcd");
  ASSERT_EQ(f.points.size(), 2u);
  EXPECT_EQ(f.dropped_non_finite, 1u);
  EXPECT_EQ(f.points[1], Vec3(4, 5, 6));
  // binary_compressed: each field's values together, LZF-compressed, sizes first.
  const std::string soa = floats({1, nan, 4, 2, nan, 5, 3, nan, 6, 9, 9, 9});
  const std::string packed = lzf_literals(soa);
  std::string sizes(8, '\0');
  const auto c = static_cast<std::uint32_t>(packed.size()), u = static_cast<std::uint32_t>(soa.size());
  std::memcpy(sizes.data(), &c, 4);
  std::memcpy(sizes.data() + 4, &u, 4);
  f = parse_pcd(header + "DATA binary_compressed\n" + sizes + packed, "c.pcd");
  ASSERT_EQ(f.points.size(), 2u);
  EXPECT_EQ(f.points[0], Vec3(1, 2, 3));
  EXPECT_EQ(f.points[1], Vec3(4, 5, 6));
  // ascii with an integer field and COUNT 2 before x.
  f = parse_pcd("FIELDS rgb x y z\nSIZE 1 8 8 8\nTYPE U F F F\nCOUNT 2 1 1 1\nWIDTH 1\nPOINTS 1\nDATA ascii\n7 8 1.5 2.5 3.5\n", "a.pcd");
  ASSERT_EQ(f.points.size(), 1u);
  EXPECT_EQ(f.points[0], Vec3(1.5, 2.5, 3.5));
}

TEST(CloudIo, LzfBackReferencesCopyOverlappingRuns) {
  // "abc" as a literal, then a back reference of 6 bytes at distance 3.
  const std::string in = std::string("\x02" "abc", 4) + std::string("\x80\x02", 2);
  EXPECT_EQ(lzf_decompress(in, 9, "x"), "abcabcabc");
  EXPECT_THROW(lzf_decompress(in, 8, "x"), Error);                         // more than promised
  EXPECT_THROW(lzf_decompress(std::string("\x80\x05", 2), 9, "x"), Error);  // before the start
  EXPECT_THROW(lzf_decompress(std::string("\x05" "ab", 3), 6, "x"), Error); // truncated literal
}

TEST(CloudIo, PlyBinaryBigEndianWithFacesAfterTheVertices) {
  std::string body;
  for (float v : {1.0F, -2.0F, 0.5F}) {
    std::uint32_t bits = 0;
    std::memcpy(&bits, &v, 4);
    for (int k = 3; k >= 0; --k) body.push_back(static_cast<char>((bits >> (8 * k)) & 0xff));
  }
  body.push_back(static_cast<char>(200));  // an uchar property after z
  const std::string ply = "ply\nformat binary_big_endian 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
                          "property float z\nproperty uchar red\nelement face 0\nproperty list uchar int vertex_indices\n"
                          "end_header\n" + body;
  const PointCloudFile f = parse_ply(ply, "p.ply");
  ASSERT_EQ(f.points.size(), 1u);
  EXPECT_EQ(f.points[0], Vec3(1, -2, 0.5));
}

TEST(CloudIo, KittiFramesAreFloat32Quadruples) {
  const PointCloudFile f = parse_kitti_bin(floats({1, 2, 3, 0.5F, 4, 5, 6, 0.25F}), "f.bin");
  ASSERT_EQ(f.points.size(), 2u);
  EXPECT_EQ(f.points[1], Vec3(4, 5, 6));
  try {
    parse_kitti_bin(std::string(20, '\0'), "f.bin");
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.field(), "size");
  }
}

TEST(CloudIo, MalformedFilesNameTheirField) {
  const std::string ok = "FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 2\nPOINTS 2\n";
  const auto pcd = [](const std::string& text) { return [text] { parse_pcd(text, "c.pcd"); }; };
  EXPECT_EQ(error_field(pcd("FIELDS x y\nSIZE 4 4\nTYPE F F\nWIDTH 1\nDATA ascii\n1 2\n")), "FIELDS");
  EXPECT_EQ(error_field(pcd("FIELDS x y z\nSIZE 4 4\nTYPE F F F\nWIDTH 1\nDATA ascii\n1 2 3\n")), "FIELDS");
  EXPECT_EQ(error_field(pcd("FIELDS x y z\nSIZE 3 4 4\nTYPE F F F\nWIDTH 1\nDATA ascii\n1 2 3\n")), "TYPE");
  EXPECT_EQ(error_field(pcd(ok)), "DATA");                                        // no DATA line
  EXPECT_EQ(error_field(pcd(ok + "DATA ascii\n1 2 3\n")), "POINTS");               // one point short
  EXPECT_EQ(error_field(pcd(ok + "DATA ascii\n1 2 3\n1 2 x\n")), "z");
  EXPECT_EQ(error_field(pcd(ok + "DATA ascii\n1 2 3\n1 2\n")), "DATA");
  EXPECT_EQ(error_field(pcd(ok + "DATA binary\n" + std::string(12, '\0'))), "DATA");  // truncated
  EXPECT_EQ(error_field(pcd("FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 99999999999\nPOINTS 99999999999\nDATA binary\n")),
            "WIDTH");
  EXPECT_EQ(error_field(pcd(ok + "DATA binary_compressed\n" + std::string(8, '\0'))), "DATA");
  EXPECT_EQ(error_field(pcd("BOGUS 1\n")), "BOGUS");
  EXPECT_EQ(error_field(pcd(ok + "WIDTH 3\nDATA ascii\n")), "POINTS");  // WIDTH x HEIGHT != POINTS
  const auto ply = [](const std::string& text) { return [text] { parse_ply(text, "c.pcd"); }; };
  EXPECT_EQ(error_field(ply("ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\n"
                            "property float z\nend_header\n1 2 3\n")), "element vertex");
  EXPECT_EQ(error_field(ply("ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nend_header\n1\n")), "property");
  EXPECT_EQ(error_field(ply("ply\nformat xml 1.0\n")), "format");
  EXPECT_EQ(error_field(ply("ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\n")), "end_header");
  EXPECT_EQ(error_field(ply("ply\nformat binary_little_endian 1.0\nelement vertex 5\nproperty float x\nproperty float y\n"
                            "property float z\nend_header\n" + std::string(12, '\0'))), "element vertex");
  EXPECT_EQ(error_field(ply("pli\n")), "ply");
  // A control character in a field name is escaped in the message.
  try {
    parse_pcd("BO\x1b[2JGUS 1\n", "c.pcd");
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()).find('\x1b'), std::string::npos);
  }
}

// Files are judged by their head and size before they are read: each is read in a child whose
// address space (200 MB) could not hold the file (3 GB, or a KITTI frame of one point more than the
// limit, 800 MB; sparse on disk), and must be refused with its own head's error (1: the reader
// returned, 2: another error, 3: out of memory: read first).
TEST(CloudIo, FilesAreJudgedByTheirHeadAndSizeBeforeTheyAreRead) {
  if (test::kUnderAddressSanitizer) GTEST_SKIP() << "AddressSanitizer reserves more address space than a memory limit allows";
  test::ScratchDir dir;
  const std::uint64_t gib3 = std::uint64_t{3} << 30;
  const std::string pcd10 = "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH 10\nHEIGHT 1\nPOINTS 10\n";
  const std::string ply10 = "ply\nformat ascii 1.0\nelement vertex 10\nproperty float x\nproperty float y\nproperty float z\nend_header\n";
  std::string comments = "# .PCD v0.7\n";
  while (comments.size() < 70000) comments += "# a header far longer than any PCL writes\n";
  struct Row {
    std::string name, head;
    std::uint64_t size;
    std::function<void(const std::string&)> read;
    std::string says;
  };
  const auto cloud = [](const std::string& p) { read_point_cloud(p); };
  const std::vector<Row> rows = {
      {"junk.pcd", "", gib3, cloud, "unknown PCD header line"},
      {"junk.ply", "", gib3, cloud, "does not start with the line 'ply'"},
      {"junk.xyz", "", gib3, cloud, "not a point cloud: expected a PCD or PLY header"},
      {"binary.pcd", pcd10 + "DATA binary\n", gib3, cloud, "more than its header's points take (219 and 1048576 to spare)"},
      {"ascii.pcd", pcd10 + "DATA ascii\n", gib3, cloud, "more than its header's points take"},
      {"ascii.ply", ply10, gib3, cloud, "more than its header's points take"},
      {"short.pcd", pcd10 + "DATA binary\n" + std::string(20, '\0'), 0, cloud, "binary data holds 20 bytes, 120 needed"},
      {"comments.pcd", comments, gib3, cloud, "the header does not end within the first 65536 bytes"},
      {"poses.txt", "", gib3, [](const std::string& p) { read_kitti_poses(p); }, "line 1 is longer than 65536 bytes"},
      {"tum.txt", "1 0 0 0 0 0 0 1\n", gib3, [](const std::string& p) { read_pose_file(p); }, "byte 16 is a NUL"},
      {"big.bin", "", (kMaxCloudPoints + 1) * 16, cloud, "50000001 points is more than the limit of 50000000"},
  };
  for (const Row& r : rows) {
    SCOPED_TRACE(r.name);
    const std::string path = dir.file(r.name);
    test::write_text(path, r.head);
    if (r.size > 0) std::filesystem::resize_file(path, r.size);
    const pid_t child = ::fork();
    ASSERT_GE(child, 0);
    if (child == 0) {
      const rlimit limit{200u << 20, 200u << 20};
      ::setrlimit(RLIMIT_AS, &limit);
      int code = 1;
      try {
        r.read(path);
      } catch (const Error& e) {
        code = std::string(e.what()).find(r.says) != std::string::npos ? 0 : 2;
        if (code) std::fprintf(stderr, "%s\n", e.what());
      } catch (...) {
        code = 3;
      }
      ::_exit(code);
    }
    int status = 0;
    ::waitpid(child, &status, 0);
    ASSERT_TRUE(WIFEXITED(status));
    EXPECT_EQ(WEXITSTATUS(status), 0) << "1: read, 2: another error, 3: out of memory";
  }
}

TEST(CloudIo, ReadsTheSharedKittiFrames) {
  const std::string path = test::shared_path("datasets/lidar3d/kitti_odometry_mini/sequences/07/velodyne/000000.bin.gz");
  if (path.empty()) GTEST_SKIP() << "../shared/datasets/lidar3d is not here";
  const PointCloudFile f = read_point_cloud(path);
  EXPECT_GT(f.points.size(), 120000u);  // SOURCES.md: 121,357-127,198 points per scan
  EXPECT_LT(f.points.size(), 128000u);
  EXPECT_EQ(f.dropped_non_finite, 0u);
}

}  // namespace
}  // namespace starnav
