// The largest image rayaccel renders or makes camera rays for, one limit for the CLI and the Python package.
#pragma once

namespace rayaccel {

/// The widest and tallest image accepted (the CLI's --res, Python's Camera.rays() and render()): larger sizes are
/// refused up front with a message rather than failing to allocate.
inline constexpr int kMaxImageSide = 16384;

}  // namespace rayaccel
