// Example camera rigs with known truth (camera/rig.h), for tests, benchmarks and docs: what a
// stereo user and a multi-camera user calibrate.
#pragma once

#include "camera/rig.h"

namespace calibench {

// Two 640 x 480 pinhole-radtan4 cameras (f ~ 500 px, k1 ~ -0.2), camera 1's centre 0.12 m to the
// right of camera 0's (and 2 mm down, 1 mm back), turned by the rotation vector (0.3, -0.5, 0.2)
// deg: a car's or a robot's forward stereo pair.
CameraRig ExampleStereoRig();

// Three 640 x 480 cameras along a 0.2 m bar, turned to the right about the vertical (camera y)
// axis (rotation vectors (0, -45, 0) and (0, -90, 0) deg): camera 0 pinhole-radtan4 looking ahead,
// camera 1 double-sphere (~190 deg field, xi -0.2, alpha 0.6) 0.1 m to the right turned 45 deg,
// camera 2 pinhole-radtan4 0.2 m to the right turned 90 deg. Camera 2
// (+-32 deg about its axis) never sees what camera 0 (+-32 deg) sees: it is linked to camera 0
// only through camera 1's wide field.
CameraRig ExampleMixedThreeCameraRig();

}  // namespace calibench
