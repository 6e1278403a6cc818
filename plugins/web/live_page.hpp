#pragma once
// The live view's one page (HTML, CSS and JS in one text, compiled into the binary:
// nothing is fetched at run time). It subscribes to /events (Server-Sent Events: init,
// pose, status) and draws the LED map, the trajectory, the pose with its 95 % ellipse,
// and shows LEDs in view, mode, latency, per-source rates and drops, and the camera
// picture (frame.jpg, a few a second) with the identified LEDs circled.
#include <string_view>

namespace luxloc {

std::string_view live_page_html();

}  // namespace luxloc
