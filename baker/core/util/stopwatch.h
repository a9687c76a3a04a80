#pragma once
/// Seconds since a moment: how the core stages report their own time
/// (RenderStats, ClothScene::setup_seconds).

#include <chrono>

namespace clothbake {

inline double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace clothbake
