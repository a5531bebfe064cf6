// bemsurg/haptics.hpp: the haptics module in one include (docs/design.md, "Module order").
#pragma once

/// \defgroup haptics Haptics
/// \brief The action language of a session (its model; the JSON reader is in io), the haptic loop at 1 kHz, devices (scripted, recording, UDP), the force limiter and scripted sessions. Compiled as the library bemsurg::haptics and so not in bemsurg/bemsurg.hpp.
///
/// Headers (each can be included on its own for faster builds):
/// - action_script.hpp
/// - background_task.hpp
/// - background_threads.hpp
/// - felt_force.hpp
/// - force_limiter.hpp
/// - haptic_device.hpp
/// - haptic_loop.hpp
/// - loop_statistics.hpp
/// - model_crossfade.hpp
/// - recording_device.hpp
/// - scripted_device.hpp
/// - session.hpp
/// - spsc_ring.hpp
/// - surface_cut_hook.hpp
/// - triple_buffer.hpp
/// - udp_device.hpp

#include "bemsurg/haptics/action_script.hpp"
#include "bemsurg/haptics/background_task.hpp"
#include "bemsurg/haptics/background_threads.hpp"
#include "bemsurg/haptics/felt_force.hpp"
#include "bemsurg/haptics/force_limiter.hpp"
#include "bemsurg/haptics/haptic_device.hpp"
#include "bemsurg/haptics/haptic_loop.hpp"
#include "bemsurg/haptics/loop_statistics.hpp"
#include "bemsurg/haptics/model_crossfade.hpp"
#include "bemsurg/haptics/recording_device.hpp"
#include "bemsurg/haptics/scripted_device.hpp"
#include "bemsurg/haptics/session.hpp"
#include "bemsurg/haptics/spsc_ring.hpp"
#include "bemsurg/haptics/surface_cut_hook.hpp"
#include "bemsurg/haptics/triple_buffer.hpp"
#include "bemsurg/haptics/udp_device.hpp"
