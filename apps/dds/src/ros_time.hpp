#pragma once
// The wall-clock stamp of a message leaving Flipper, as ROS 2's builtin_interfaces/Time
// (seconds and nanoseconds since the epoch; docs/ros2.md "Topics and types"). Header-only.
#include <chrono>
#include <cstdint>

#include "builtin_interfaces/msg/Time.h"

namespace flipper::dds {

inline builtin_interfaces_msg_dds__Time_ now_stamp() {
  const auto ns = std::chrono::duration_cast<std::chrono::nanoseconds>(
                      std::chrono::system_clock::now().time_since_epoch())
                      .count();
  builtin_interfaces_msg_dds__Time_ t{};
  t.sec_ = static_cast<int32_t>(ns / 1000000000);
  t.nanosec_ = static_cast<uint32_t>(ns % 1000000000);
  return t;
}

}  // namespace flipper::dds
