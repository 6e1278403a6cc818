// `calib camera`: Zhang calibration on a rendered chessboard set with known intrinsics, and
// on OpenCV's own sample photographs (opencv-doc's left*.jpg) against OpenCV's sample flow.
#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <random>

#include "calib/camera_calibrator.hpp"
#include "core/vlc/camera_model.hpp"
#include "test_support.hpp"

using namespace luxloc;

namespace {

struct TrueCamera {
  cv::Matx33d K{600.0, 0.0, 322.5, 0.0, 601.5, 236.0, 0.0, 0.0, 1.0};
  cv::Vec<double, 5> dist{-0.12, 0.05, 0.0005, -0.0004, 0.0};
  cv::Size size{640, 480};
};

// Renders the 9x6-corner board (10 x 7 squares of `square` m, a white margin) seen from
// (rvec, tvec): for every output pixel, undistort to the ideal image plane, intersect the
// ray with the board plane (inverse homography) and sample a supersampled texture.
cv::Mat render_board(const TrueCamera& cam, const cv::Vec3d& rvec, const cv::Vec3d& tvec, double square,
                     std::mt19937_64& rng, const cv::Vec<double, 5>& dist) {
  constexpr int kPxPerSquare = 60;
  const int margin = kPxPerSquare;  // one square of white around
  cv::Mat tex(7 * kPxPerSquare + 2 * margin, 10 * kPxPerSquare + 2 * margin, CV_8UC1, cv::Scalar(235));
  for (int r = 0; r < 7; ++r)
    for (int c = 0; c < 10; ++c)
      if ((r + c) % 2 == 0)
        tex(cv::Rect(margin + c * kPxPerSquare, margin + r * kPxPerSquare, kPxPerSquare, kPxPerSquare)) = 25;
  cv::GaussianBlur(tex, tex, cv::Size(0, 0), 1.0);
  // Board coordinates: inner corner (0, 0) at square (1, 1) of the texture.
  const double px_per_m = kPxPerSquare / square;
  cv::Matx33d R;
  cv::Rodrigues(rvec, R);
  // Ideal normalised image point -> board (x, y): inverse of [r1 r2 t].
  const cv::Matx33d H(R(0, 0), R(0, 1), tvec[0], R(1, 0), R(1, 1), tvec[1], R(2, 0), R(2, 1), tvec[2]);
  const cv::Matx33d Hi = H.inv();
  std::vector<cv::Point2f> pix;
  pix.reserve(static_cast<std::size_t>(cam.size.area()));
  for (int v = 0; v < cam.size.height; ++v)
    for (int u = 0; u < cam.size.width; ++u) pix.emplace_back(static_cast<float>(u), static_cast<float>(v));
  std::vector<cv::Point2f> ideal;
  cv::undistortPoints(pix, ideal, cam.K, dist);  // normalised coordinates
  cv::Mat mapx(cam.size, CV_32FC1), mapy(cam.size, CV_32FC1);
  for (int v = 0; v < cam.size.height; ++v)
    for (int u = 0; u < cam.size.width; ++u) {
      const cv::Point2f& n = ideal[static_cast<std::size_t>(v * cam.size.width + u)];
      const cv::Vec3d b = Hi * cv::Vec3d(n.x, n.y, 1.0);
      mapx.at<float>(v, u) = static_cast<float>(margin + kPxPerSquare + b[0] / b[2] * px_per_m - 0.5);
      mapy.at<float>(v, u) = static_cast<float>(margin + kPxPerSquare + b[1] / b[2] * px_per_m - 0.5);
    }
  // Area sampling: the texture is ~4x finer than the image; pre-blur so remap does not alias.
  cv::Mat smooth;
  cv::GaussianBlur(tex, smooth, cv::Size(0, 0), 1.5);
  cv::Mat img;
  cv::remap(smooth, img, mapx, mapy, cv::INTER_LINEAR, cv::BORDER_CONSTANT, cv::Scalar(128));
  cv::Mat noise(img.size(), CV_32FC1);
  std::normal_distribution<float> n(0.0f, 2.0f);
  for (int v = 0; v < img.rows; ++v)
    for (int u = 0; u < img.cols; ++u) noise.at<float>(v, u) = n(rng);
  cv::Mat f;
  img.convertTo(f, CV_32FC1);
  f += noise;
  f.convertTo(img, CV_8UC1);
  return img;
}

std::vector<std::pair<cv::Vec3d, cv::Vec3d>> poses() {
  // Board centre ~(0.1125, 0.0625) m from inner corner 0; views tilted up to ~35 deg.
  std::vector<std::pair<cv::Vec3d, cv::Vec3d>> p;
  const double tilts[][3] = {{0.0, 0.0, 0.0},   {0.5, 0.0, 0.1},  {-0.5, 0.1, -0.1}, {0.0, 0.55, 0.2},
                             {0.1, -0.55, 0.0}, {0.4, 0.4, 0.3},  {-0.4, -0.35, 0.5}, {0.35, -0.4, -0.4},
                             {-0.3, 0.45, 0.0}, {0.2, 0.2, 1.2},  {-0.2, -0.2, -1.0}, {0.6, -0.1, 0.2}};
  int k = 0;
  for (const auto& t : tilts) {
    const cv::Vec3d rvec(t[0], t[1], t[2]);
    cv::Matx33d R;
    cv::Rodrigues(rvec, R);
    const cv::Vec3d centre_inB(0.1, 0.0625, 0.0);
    const double z = 0.42 + 0.03 * (k % 4);
    const cv::Vec3d offset(0.03 * ((k % 3) - 1), 0.025 * ((k % 2) ? 1 : -1), z);
    p.emplace_back(rvec, offset - R * centre_inB);  // board centre at `offset` in the camera
    ++k;
  }
  return p;
}

}  // namespace

TEST_CASE("calib camera: rendered chessboards reproduce focal length within 0.5 % and principal point within 2 px",
          "[calib]") {
  const TrueCamera cam;
  std::mt19937_64 rng(5);
  std::vector<cv::Mat> images;
  std::vector<std::string> names;
  for (const auto& [r, t] : poses()) {
    images.push_back(render_board(cam, r, t, 0.025, rng, cam.dist));
    names.push_back("view" + std::to_string(names.size()));
  }
  // A view that does not fit the camera model (strong barrel of another lens): rejected.
  const auto bad_pose = poses()[5];
  images.push_back(render_board(cam, bad_pose.first, bad_pose.second, 0.025, rng, {0.45, 0.0, 0.0, 0.0, 0.0}));
  names.push_back("bad");
  images.push_back(cv::Mat(480, 640, CV_8UC1, cv::Scalar(128)));  // no board at all
  names.push_back("blank");

  calib::CameraCalibOptions o;
  const calib::CameraCalibResult r = calib::calibrate_camera(images, names, o);
  const CameraModel& c = r.camera;
  WARN("rendered set: fx " << c.fx << " fy " << c.fy << " cx " << c.cx << " cy " << c.cy << " k1 " << c.dist[0]
                           << " k2 " << c.dist[1] << " rms " << r.rms_px << " px, " << r.used() << " views used, "
                           << r.rounds << " rounds, bad view " << r.views[12].rms_px << " px");
  std::string views;
  for (const auto& v : r.views) views += v.name + (v.found ? (v.used ? " used " : " rejected ") : " none ") + std::to_string(v.rms_px) + "; ";
  INFO(views);
  CHECK(r.views.size() == 14);
  CHECK_FALSE(r.views[13].found);
  REQUIRE(r.views[12].found);
  CHECK_FALSE(r.views[12].used);  // the inconsistent view was dropped
  CHECK(r.used() == 12);
  CHECK(r.rounds >= 2);
  CHECK(std::abs(c.fx / cam.K(0, 0) - 1.0) < 0.005);
  CHECK(std::abs(c.fy / cam.K(1, 1) - 1.0) < 0.005);
  CHECK(std::abs(c.cx - cam.K(0, 2)) < 2.0);
  CHECK(std::abs(c.cy - cam.K(1, 2)) < 2.0);
  CHECK(c.dist[0] == Approx(cam.dist[0]).margin(0.03));
  CHECK(r.rms_px < 0.3);
  for (int i = 0; i < 12; ++i) CHECK(r.views[static_cast<std::size_t>(i)].rms_px < 0.5);

  // Too few boards: refused with a message.
  CHECK_THROWS_AS(calib::calibrate_camera({images[0], images[1]}, {}, o), std::invalid_argument);
}

TEST_CASE("calib camera: OpenCV's sample photographs (left*.jpg, 9x6) agree with OpenCV's calibration sample",
          "[calib]") {
  const std::filesystem::path data = "/usr/share/doc/opencv-doc/examples/data";
  std::vector<std::filesystem::path> files;
  if (std::filesystem::is_directory(data))
    for (const auto& e : std::filesystem::directory_iterator(data)) {
      const std::string n = e.path().filename().string();
      if (n.size() == 10 && n.rfind("left", 0) == 0 && e.path().extension() == ".jpg") files.push_back(e.path());
    }
  if (files.size() < 10) {
    WARN("opencv-doc's left*.jpg not installed (apt-get install opencv-doc): skipped");
    return;
  }
  std::sort(files.begin(), files.end());
  std::vector<cv::Mat> images;
  std::vector<std::string> names;
  for (const auto& f : files) {
    images.push_back(cv::imread(f.string(), cv::IMREAD_GRAYSCALE));
    names.push_back(f.filename().string());
  }
  calib::CameraCalibOptions o;  // 9x6, 25 mm: the sample's board
  const calib::CameraCalibResult ours = calib::calibrate_camera(images, names, o);

  // OpenCV's samples/cpp/calibration.cpp with its default flags (0 | FIX_K3 | USE_LU) on
  // every detected view, detection and sub-pixel refinement as it does them.
  std::vector<std::vector<cv::Point3f>> obj;
  std::vector<std::vector<cv::Point2f>> img;
  for (const cv::Mat& g : images) {
    std::vector<cv::Point2f> pts;
    if (!cv::findChessboardCorners(g, o.board, pts,
                                   cv::CALIB_CB_ADAPTIVE_THRESH | cv::CALIB_CB_FAST_CHECK | cv::CALIB_CB_NORMALIZE_IMAGE))
      continue;
    cv::cornerSubPix(g, pts, cv::Size(11, 11), cv::Size(-1, -1),
                     cv::TermCriteria(cv::TermCriteria::EPS + cv::TermCriteria::COUNT, 30, 0.0001));
    img.push_back(pts);
    obj.push_back(calib::chessboard_points(o));
  }
  cv::Mat K = cv::Mat::eye(3, 3, CV_64F), D = cv::Mat::zeros(8, 1, CV_64F);
  std::vector<cv::Mat> rv, tv;
  const double rms = cv::calibrateCamera(obj, img, images[0].size(), K, D, rv, tv, cv::CALIB_FIX_K3 | cv::CALIB_USE_LU);
  const CameraModel& c = ours.camera;
  WARN("left*.jpg: ours fx " << c.fx << " fy " << c.fy << " cx " << c.cx << " cy " << c.cy << " k1 " << c.dist[0]
                             << " rms " << ours.rms_px << " (" << ours.used() << "/" << img.size()
                             << " views); OpenCV sample fx " << K.at<double>(0, 0) << " fy " << K.at<double>(1, 1)
                             << " cx " << K.at<double>(0, 2) << " cy " << K.at<double>(1, 2) << " k1 "
                             << D.at<double>(0) << " rms " << rms);
  std::string per_view;
  for (const auto& v : ours.views)
    per_view += v.name + " " + std::to_string(v.rms_px).substr(0, 5) + (v.used ? "" : " REJECTED") + "; ";
  WARN("left*.jpg per view: " << per_view);
  CHECK(img.size() == 13);
  CHECK(ours.used() >= 12);
  CHECK(std::abs(c.fx / K.at<double>(0, 0) - 1.0) < 0.01);
  CHECK(std::abs(c.fy / K.at<double>(1, 1) - 1.0) < 0.01);
  CHECK(std::abs(c.cx - K.at<double>(0, 2)) < 3.0);
  CHECK(std::abs(c.cy - K.at<double>(1, 2)) < 3.0);
  CHECK(ours.rms_px <= rms + 1e-9);  // dropping a bad view can only lower the error

  // Without rejection it is the very same computation: identical numbers.
  o.reject_factor = 1e9;
  const calib::CameraCalibResult same = calib::calibrate_camera(images, names, o);
  CHECK(same.used() == img.size());
  CHECK(same.camera.fx == Approx(K.at<double>(0, 0)).epsilon(1e-9));
  CHECK(same.camera.cy == Approx(K.at<double>(1, 2)).epsilon(1e-9));
  CHECK(same.rms_px == Approx(rms).epsilon(1e-9));
}

TEST_CASE("luxloc calib camera: a folder of board images -> camera.yaml that run takes, bad input exits 2", "[calib]") {
  const TrueCamera cam;
  std::mt19937_64 rng(9);
  const auto dir = test::scratch_dir("calib_camera");
  const auto images = dir / "images";
  std::filesystem::create_directories(images);
  int k = 0;
  for (const auto& [r, t] : poses()) {
    if (k % 2 == 0) cv::imwrite((images / ("board" + std::to_string(k) + ".png")).string(), render_board(cam, r, t, 0.025, rng, cam.dist));
    ++k;
  }
  test::write_text(images / "notes.txt", "not an image");
  const auto calibrate = [&images](const std::filesystem::path& out, const std::string& extra) {
    return test::run_luxloc("calib camera --images '" + images.string() + "' --board 9x6 --square 0.025 --out '" +
                            out.string() + "'" + extra);
  };
  const auto out = dir / "camera.yaml";
  const auto r = calibrate(out, " --row-time-us 28.5");
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  CHECK(r.output.find("6 boards found, 6 used") != std::string::npos);
  const CameraModel c = CameraModel::load(out.string());
  CHECK(c.width == 640);
  CHECK(std::abs(c.fx / 600.0 - 1.0) < 0.005);
  CHECK(std::abs(c.cy - 236.0) < 2.0);
  CHECK(c.row_time_s == Approx(28.5e-6));
  CHECK(c.row_time_known);

  // Without --row-time-us the file holds no row time: a guess must not read as measured
  // (run --camera would shift V4L2 end-of-frame stamps by it, calib ledmap plan plan with it).
  const auto unmeasured = dir / "unmeasured.yaml";
  const auto u = calibrate(unmeasured, "");
  INFO(u.output);
  REQUIRE(u.exit_code == 0);
  CHECK(u.output.find("no row_time_us written") != std::string::npos);
  CHECK(test::read_text(unmeasured).find("row_time_us") == std::string::npos);
  CHECK_FALSE(CameraModel::load(unmeasured.string()).row_time_known);
  const auto slip = test::run_luxloc("calib camera --images '" + images.string() + "' --out '" +
                                     (dir / "x.yaml").string() + "' --row-time-us 0.03");
  CHECK(slip.exit_code == 2);
  CHECK(slip.output.find("--row-time-us") != std::string::npos);

  const auto empty = dir / "empty";
  std::filesystem::create_directories(empty);
  cv::imwrite((empty / "gray.png").string(), cv::Mat(480, 640, CV_8UC1, cv::Scalar(128)));
  const auto bad = test::run_luxloc("calib camera --images '" + empty.string() + "' --out '" + (dir / "x.yaml").string() + "'");
  CHECK(bad.exit_code == 2);
  CHECK(bad.output.find("found in 0 of 1 images") != std::string::npos);
  const auto bad_board = test::run_luxloc("calib camera --images '" + images.string() + "' --board 9by6 --out '" +
                                          (dir / "x.yaml").string() + "'");
  CHECK(bad_board.exit_code == 2);
  CHECK(bad_board.output.find("--board") != std::string::npos);
}

TEST_CASE("luxloc calib camera --playback: boards collected from a session's frames, distinct views only", "[calib]") {
  const TrueCamera cam;
  std::mt19937_64 rng(10);
  const auto dir = test::scratch_dir("calib_camera_stream");
  const auto s = dir / "session";
  std::filesystem::create_directories(s / "frames");
  // Each pose held for 3 frames at 2 fps (repeats must be skipped), a blank frame between.
  std::string csv = "t,file\n";
  int n = 0;
  for (const auto& [r, t] : poses()) {
    const cv::Mat board = render_board(cam, r, t, 0.025, rng, cam.dist);
    for (int rep = 0; rep < 4; ++rep) {
      char name[32];
      std::snprintf(name, sizeof name, "frames/%04d.png", n);
      cv::imwrite((s / name).string(), rep < 3 ? board : cv::Mat(480, 640, CV_8UC1, cv::Scalar(90)));
      csv += std::to_string(0.5 * n) + "," + name + "\n";
      ++n;
    }
  }
  test::write_text(s / "frames.csv", csv);
  const auto out = dir / "camera.yaml";
  const auto r = test::run_luxloc("calib camera --playback '" + s.string() + "' --interval 0.4 --out '" + out.string() +
                                  "' --row-time-us 30");
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  const std::size_t n_poses = poses().size();
  CHECK(r.output.find(std::to_string(n_poses) + " images") != std::string::npos);  // one view per pose, repeats skipped
  const CameraModel c = CameraModel::load(out.string());
  CHECK(std::abs(c.fx / 600.0 - 1.0) < 0.005);
  CHECK(std::abs(c.cx - 322.5) < 2.0);
  CHECK(test::run_luxloc("calib camera --out '" + out.string() + "'").exit_code == 2);  // no input
}
