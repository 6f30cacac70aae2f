// The bad-input matrix, part 2 (part 1, configuration files: bad_input_test.cc): inputs that are
// well-formed but cannot be measured or solved, image folders that are empty or broken, targets
// that do not match their images, and output directories that cannot be written. Each ends in a
// failed (or diverged) row with its reason while the other rows are still produced, or in an error
// naming the file and the reason. Disk full mid-run: disk_full_test.sh.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "bench/app/frames_io.h"
#include "bench/config/config_io.h"
#include "bench/run/run_dir.h"
#include "bench/run/runner.h"
#include "calib/calibrate.h"
#include "calib/calibrate_report.h"
#include "calib/image_points.h"
#include "io/target_io.h"
#include "tests/common/rendered_folder.h"

namespace calibench {
namespace {

namespace fs = std::filesystem;

// Per process: CTest runs each test of this file as its own process, in parallel.
std::string TempPath(const std::string& name) {
  const std::string unique = "bad_run_" + std::to_string(::getpid()) + "_" + name;
  return (fs::path(testing::TempDir()) / unique).lexically_normal().string();
}

// Removes this process's files at exit.
class RemoveTempFiles : public testing::Environment {
 public:
  void TearDown() override {
    const std::string prefix = "bad_run_" + std::to_string(::getpid()) + "_";
    std::error_code ec;
    for (const auto& entry : fs::directory_iterator(testing::TempDir(), ec)) {
      if (entry.path().filename().string().rfind(prefix, 0) == 0) fs::remove_all(entry.path(), ec);
    }
  }
};
testing::Environment* const kRemoveTempFiles =
    testing::AddGlobalTestEnvironment(new RemoveTempFiles);

// Thesis camera 1 looking along world +y from (0, -2, 0.5), with `points` and `extra` lines.
std::string Scenario(const std::string& points, const std::string& extra = "") {
  return "scenario:\n"
         "  name: t\n"
         "  duration_s: 10\n"
         "  truth:\n"
         "    intrinsics: {fku_px: 800, fkv_px: 810, phi_deg: 88, u0_px: 320, v0_px: 240}\n"
         "    R_C: [[-1, 0, 0], [0, 0, 1], [0, 1, 0]]\n"
         "    x_C: [0, -2, 0.5]\n"
         "  methods: {dlt: {enabled: true}, ceres: {enabled: true}, zhang: {enabled: true}}\n"
         "  points: " +
         points + "\n" + extra;
}

// Eight points in front of the camera, not coplanar.
const std::string kGoodPoints =
    "{list: [[0, 5, 0], [1, 6, 1], [-1, 7, 0.5], [0.5, 5.5, -1], [2, 8, 0], [-2, 6, 1], "
    "[0, 9, 2], [1, 4, 1]]}";

std::vector<RunRow> RunYaml(const std::string& yaml) {
  RunConfig config;
  std::string why;
  EXPECT_TRUE(LoadRunConfigFromString(yaml, "run.yaml", &config, &why)) << why;
  return RunScenarios(config.scenarios, RunOptions());
}

const RunRow& RowOf(const std::vector<RunRow>& rows, const std::string& method, int point = 0) {
  for (const RunRow& r : rows) {
    if (r.method == method && r.point == point) return r;
  }
  static const RunRow kNone;
  ADD_FAILURE() << "no " << method << " row at sweep point " << point;
  return kNone;
}

// A failed row carries no number: every estimate is NaN, so no summary can use it by mistake.
void ExpectFailed(const RunRow& row, const std::string& status, const std::string& reason) {
  EXPECT_EQ(row.status, status) << row.method << ": " << row.message;
  EXPECT_NE(row.message.find(reason), std::string::npos) << row.method << ": " << row.message;
  EXPECT_TRUE(std::isnan(row.fku_px) && std::isnan(row.err_fku_px))
      << row.method << ": " << row.fku_px;
}

TEST(BadTrial, PointBehindTheCameraFailsEveryMethodNamingThePoint) {
  const std::vector<RunRow> rows =
      RunYaml(Scenario("{list: [[0, 5, 0], [1, 6, 1], [-1, 7, 0.5], [0.5, 5.5, -1], "
                       "[2, 8, 0], [-2, -6, 1], [0, 9, 2]]}"));
  ASSERT_EQ(rows.size(), 5u);  // adaptive, dlt, zhang, zhang_handeye, ceres.
  for (const RunRow& r : rows) {
    ExpectFailed(r, "failed", "feature point 5 is behind the camera at t = 0 s");
  }
}

TEST(BadTrial, PointOutsideTheImageFailsUnlessKept) {
  const std::string points =
      "{list: [[0, 5, 0], [1, 6, 1], [-1, 7, 0.5], [0.5, 5.5, -1], [2, 8, 0], [-20, 6, 1], "
      "[0, 9, 2], [1, 4, 1]]}";
  const std::vector<RunRow> rows = RunYaml(Scenario(points, "  image_size: [640, 480]\n"));
  ExpectFailed(RowOf(rows, "dlt"), "failed", "feature point 5 projects outside the 640 x 480");
  // outside_image: keep measures it anyway (the thesis model): noise-free, dlt is exact.
  const std::vector<RunRow> kept = RunYaml(
      Scenario(points, "  measurements: {outside_image: keep}\n  image_size: [640, 480]\n"));
  EXPECT_EQ(RowOf(kept, "dlt").status, "ok");
  EXPECT_NEAR(RowOf(kept, "dlt").fku_px, 800.0, 1e-6);
}

TEST(BadTrial, TooFewPointsFailTheDltAndFlagTheAdaptiveEstimate) {
  // Fixed camera, 5 points: the DLT needs 6 correspondences.
  const std::vector<RunRow> fixed =
      RunYaml(Scenario("{list: [[0, 5, 0], [1, 6, 1], [-1, 7, 0.5], [0.5, 5.5, -1], [2, 8, 0]]}",
                       "  case: fixed_camera\n  motion: {preset: none}\n"));
  ExpectFailed(RowOf(fixed, "dlt"), "failed", "the DLT needs at least 6 distinct points, got 5");
  ExpectFailed(RowOf(fixed, "ceres"), "failed", "initialisation (dlt) failed");
  // Moving camera, 4 points, small motion: the adaptive estimate fits the data exactly but is not
  // the camera (the thesis needed >= 7 points with this motion); its row says so.
  const std::vector<RunRow> moving =
      RunYaml(Scenario("{list: [[0, 5, 0], [1, 6, 1], [-1, 7, 0.5], [0.5, 5.5, -1]]}",
                       "  motion: {preset: small}\n"));
  const RunRow& adaptive = RowOf(moving, "adaptive");
  EXPECT_NE(adaptive.message.find("not identifiable: persistent-excitation index"),
            std::string::npos)
      << adaptive.message;
  EXPECT_GT(adaptive.theta_err_norm, 1.0);  // It is indeed wrong.
}

TEST(BadTrial, CoplanarPointsFailTheDltWithTheReason) {
  const std::vector<RunRow> rows =
      RunYaml(Scenario("{list: [[0, 5, 0], [1, 5, 1], [-1, 5, 0.5], [0.5, 5, -1], [2, 5, 0], "
                       "[-2, 5, 1], [0, 5, 2], [1, 5, -0.5]]}",
                       "  case: fixed_camera\n  motion: {preset: none}\n"));
  ExpectFailed(RowOf(rows, "dlt"), "failed", "coplanar");
  ExpectFailed(RowOf(rows, "zhang"), "failed", "zhang needs planar boards");
}

TEST(BadTrial, DivergingGainIsReportedAndTheSweepGoesOn) {
  const std::vector<RunRow> rows =
      RunYaml(Scenario(kGoodPoints) + "sweep:\n  - field: methods.adaptive.alpha\n" +
              "    values: [1000, 1.0e12]\n");
  const RunRow& fine = RowOf(rows, "adaptive", 0);
  EXPECT_EQ(fine.status, "ok") << fine.message;
  ExpectFailed(RowOf(rows, "adaptive", 1), "diverged", "step size underflow");
  // The batch methods do not depend on alpha: their rows exist at both points, equal and exact.
  EXPECT_EQ(RowOf(rows, "dlt", 1).status, "ok");
  EXPECT_EQ(RowOf(rows, "dlt", 1).fku_px, RowOf(rows, "dlt", 0).fku_px);
}

// ---- Image folders (calibrate --images) ----

const CameraIntrinsics kImageCamera{600, 605, 90, 322, 238, 0, 0};

// 6 views of a 6 x 6 tag36h11 grid of 3 cm tags, rendered once for the image cases.
const std::string& GoodFolder() {
  static const std::string dir = [] {
    std::string d = TempPath("good_views");
    AprilGrid grid;
    grid.tag_size_m = 0.03;
    grid.black_tag_border = 2;  // Kalibr's layout, the target YAML's default.
    RenderedFolderOptions options;
    options.views = 6;
    EXPECT_EQ(WriteRenderedAprilGridFolder(d, kImageCamera, grid, options), 6);
    return d;
  }();
  return dir;
}

CalibrationTarget Target(const std::string& yaml) {
  const std::string path = TempPath("target.yaml");
  std::ofstream(path) << yaml;
  CalibrationTarget target;
  std::string why;
  EXPECT_TRUE(LoadTargetYaml(path, &target, &why)) << why;
  return target;
}
const std::string kGridYaml =  // Rendered by calibench: no corner squares.
    "target_type: aprilgrid\ntagCols: 6\ntagRows: 6\ntagSize: 0.03\ntagSpacing: 0.3\n"
    "cornerSquares: false\n";

struct FolderResult {
  bool ok = false;
  std::string why;
  ImageFolderReport report;
  PointData data;
  std::vector<int> used;
};
FolderResult LoadFolder(const std::string& dir, const std::string& target_yaml = kGridYaml) {
  FolderResult r;
  r.ok = LoadImagePoints(dir, Target(target_yaml), &r.data, &r.report, &r.used, &r.why);
  return r;
}

// A copy of the good folder plus `extra` files (name -> bytes).
std::string FolderWith(const std::string& name,
                       const std::vector<std::pair<std::string, std::string>>& extra) {
  std::string dir = TempPath(name);
  fs::remove_all(dir);
  fs::copy(GoodFolder(), dir);
  for (const auto& [file, bytes] : extra) {
    std::ofstream(fs::path(dir) / file, std::ios::binary) << bytes;
  }
  return dir;
}

std::string FileBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

const ImageResult& ImageNamed(const ImageFolderReport& report, const std::string& file) {
  for (const ImageResult& r : report.images) {
    if (r.file == file) return r;
  }
  static const ImageResult kNone;
  ADD_FAILURE() << file << " not listed";
  return kNone;
}

TEST(BadImages, EmptyOrMissingFolderIsAnErrorNamingIt) {
  const std::string empty = TempPath("empty");
  fs::remove_all(empty);
  fs::create_directories(empty);
  std::ofstream(empty + "/notes.txt") << "not an image";
  FolderResult r = LoadFolder(empty);
  EXPECT_FALSE(r.ok);
  EXPECT_EQ(r.why, empty + ": no images (png, jpg, jpeg, tif, tiff, bmp) in the folder");
  r = LoadFolder(empty + "/absent");
  EXPECT_FALSE(r.ok);
  EXPECT_NE(r.why.find(empty + "/absent: cannot list the folder"), std::string::npos) << r.why;
}

TEST(BadImages, ZeroByteTruncatedAndNonImagesAreSkippedWithTheirReason) {
  const std::string png = FileBytes(GoodFolder() + "/view0.png");
  const std::string dir = FolderWith("broken", {{"a_zero.png", ""},
                                                {"b_truncated.png", png.substr(0, png.size() / 3)},
                                                {"c_text.jpg", "this is not a jpeg"}});
  const FolderResult r = LoadFolder(dir);
  ASSERT_TRUE(r.ok) << r.why;  // The 6 good views still calibrate.
  EXPECT_EQ(r.report.used, 6);
  EXPECT_EQ(ImageNamed(r.report, "a_zero.png").reason, "unreadable: empty file (0 bytes)");
  EXPECT_EQ(ImageNamed(r.report, "b_truncated.png").reason,
            "unreadable: cannot be decoded (not an image, or truncated)");
  EXPECT_EQ(ImageNamed(r.report, "c_text.jpg").reason,
            "unreadable: cannot be decoded (not an image, or truncated)");
}

TEST(BadImages, ImageOfAnotherSizeIsSkippedNamingBothSizes) {
  const cv::Mat small(240, 320, CV_8UC1, cv::Scalar(128));
  std::vector<uint8_t> bytes;
  ASSERT_TRUE(cv::imencode(".png", small, bytes));
  const std::string dir =
      FolderWith("sizes", {{"z_small.png", std::string(bytes.begin(), bytes.end())}});
  const FolderResult r = LoadFolder(dir);
  ASSERT_TRUE(r.ok) << r.why;
  EXPECT_EQ(ImageNamed(r.report, "z_small.png").reason,
            "size 320x240 differs from the first image's 640x480");
  EXPECT_FALSE(ImageNamed(r.report, "z_small.png").used);
}

TEST(BadImages, WrongFamilyOrIdsReportTheDetectionRate) {
  FolderResult r = LoadFolder(GoodFolder(), kGridYaml + "tagFamily: tagStandard41h12\n");
  EXPECT_FALSE(r.ok);
  EXPECT_NE(r.why.find("found in none of 6 images"), std::string::npos) << r.why;
  // tagStandard41h12 decodes at most a stray false positive in tag36h11 tags: a rate near 0.
  EXPECT_NE(r.why.find("of 216 possible tags detected (detection rate 0.0"), std::string::npos)
      << r.why;
  r = LoadFolder(GoodFolder(), kGridYaml + "codeOffset: 100\n");
  EXPECT_FALSE(r.ok);
  EXPECT_NE(r.why.find("(detection rate 0.000), 216 unknown ids"), std::string::npos) << r.why;
}

TEST(BadImages, WrongSpacingIsFlaggedByTheReprojectionError) {
  const std::string& right_yaml = kGridYaml;
  std::string wrong = kGridYaml;
  wrong.replace(wrong.find("tagSpacing: 0.3"), 15, "tagSpacing: 0.5");
  const std::string& wrong_yaml = wrong;
  for (const std::string* yaml : {&right_yaml, &wrong_yaml}) {
    const FolderResult r = LoadFolder(GoodFolder(), *yaml);
    ASSERT_TRUE(r.ok) << r.why;
    EXPECT_EQ(r.report.DetectionRate(), 1.0);  // Ids decode whatever the spacing.
    CalibrateOptions options;
    options.model = LensModel::kPinhole;
    const CalibrateReport cal = CalibrateFromPoints(r.data, options);
    const std::string text = FormatImageReport(r.report, r.used, cal);
    const bool flagged = text.find("WARNING: reprojection RMS") != std::string::npos;
    EXPECT_EQ(flagged, yaml == &wrong_yaml) << "rms " << cal.ceres.rms_reproj_px << "\n" << text;
  }
}

TEST(BadImages, DetectFramesRefusesFramesOfAnotherSizeThanTheCamera) {
  RunConfig config;
  std::string why;
  ASSERT_TRUE(LoadRunConfig(std::string(CALIBENCH_SOURCE_DIR) + "/tests/fixtures/sim03_rig.yaml",
                            &config, &why))
      << why;
  ScenarioConfig s = config.scenarios[0];
  const std::string dir = TempPath("frames");
  FramesOptions options;
  options.max_frames = 1;
  int frames = 0;
  ASSERT_TRUE(WriteRenderedFrames(s, options, dir, &frames, &why)) << why;
  s.image_width = 800;  // The frames are 640 x 480.
  DetectionStats stats;
  EXPECT_FALSE(DetectFrames(s, options, dir, &stats, &why));
  EXPECT_EQ(why, dir + "/frame_000000.png: image is 640 x 480 px, but scenario '" + s.name +
                     "' has image_size [800, 480]");
}

// ---- Output directories ----

TEST(BadOutput, UnwritableOutputDirectoryIsAnErrorNamingIt) {
  RunConfig config;
  std::string why;
  ASSERT_TRUE(LoadRunConfigFromString(Scenario(kGoodPoints), "run.yaml", &config, &why)) << why;
  const std::string file = TempPath("a_file");
  std::ofstream(file) << "x";
  RunDirOptions options;
  options.out_dir = file + "/out";  // A directory cannot be made under a regular file.
  RunDirSummary summary = RunToDirectory(config, options);
  EXPECT_FALSE(summary.ok);
  EXPECT_NE(summary.message.find(file + "/out"), std::string::npos) << summary.message;
  EXPECT_NE(summary.message.find("Not a directory"), std::string::npos) << summary.message;
  options.out_dir = file;  // An existing regular file.
  summary = RunToDirectory(config, options);
  EXPECT_FALSE(summary.ok);
  EXPECT_NE(summary.message.find(file), std::string::npos) << summary.message;
  EXPECT_EQ(FileBytes(file), "x");  // Nothing of the user's is overwritten.
}

}  // namespace
}  // namespace calibench
