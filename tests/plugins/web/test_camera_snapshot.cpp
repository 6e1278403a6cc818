// The live view's camera picture: a few frames a second kept, encoded once, LEDs circled.
#include <catch2/catch.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <thread>

#include "plugins/web/camera_snapshot.hpp"

using namespace luxloc;

TEST_CASE("The camera snapshot keeps a frame per interval and encodes it with the LEDs circled", "[plugins][web]") {
  CameraSnapshot snap(std::chrono::milliseconds(100));
  CHECK(snap.number() == 0);
  CHECK(snap.jpeg().empty());
  FrameSample f;
  f.gray = cv::Mat(360, 640, CV_8UC1, cv::Scalar(10));
  cv::circle(f.gray, {320, 180}, 30, cv::Scalar(250), -1);
  LedObservation led;
  led.uv = {320.0, 180.0};
  led.radius_px = 30.0;
  led.led_id = 7;
  led.led_index = 0;
  REQUIRE(snap.offer(f, {led}));
  CHECK(snap.number() == 1);
  CHECK_FALSE(snap.offer(f, {}));  // within the interval: not kept
  f.gray.setTo(cv::Scalar(0));     // the source reuses its buffer: the kept copy is unaffected
  const std::string jpeg = snap.jpeg();
  REQUIRE(!jpeg.empty());
  CHECK(snap.jpeg() == jpeg);  // encoded once
  const cv::Mat img = cv::imdecode(std::vector<unsigned char>(jpeg.begin(), jpeg.end()), cv::IMREAD_COLOR);
  REQUIRE(img.cols == 640);
  REQUIRE(img.rows == 360);
  CHECK(img.at<cv::Vec3b>(180, 320)[1] > 200);  // the LED, still bright in the copy
  // The circle (BGR 0, 80, 255) around it, at 1.3 radii.
  const cv::Vec3b ring = img.at<cv::Vec3b>(180, 320 + 39);
  CHECK(ring[2] > 150);
  CHECK(ring[0] < 100);
  std::this_thread::sleep_for(std::chrono::milliseconds(120));
  CHECK(snap.offer(f, {}));
  CHECK(snap.number() == 2);
  CHECK(snap.jpeg() != jpeg);
}
