// Implementation of bemsurg/haptics/haptic_device.hpp: choosing a device (null unless a driver
// is compiled in; this build has none, and says so).
#include "bemsurg/haptics/haptic_device.hpp"

namespace bemsurg::haptics {

std::unique_ptr<HapticDevice> open_default_device(std::string& reason) {
  reason =
      "bemsurg was built without a haptic device driver (no OpenHaptics / CHAI3D / libnifalcon); "
      "using the null device, whose pose the program sets";
  return std::make_unique<NullDevice>();
}

}  // namespace bemsurg::haptics
