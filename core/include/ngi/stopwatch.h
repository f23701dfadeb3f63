#pragma once
// Wall-clock stage timing for reports and progress lines (steady clock: immune to clock changes).
#include <chrono>

namespace ngi {

using StopwatchClock = std::chrono::steady_clock;

// Seconds of wall time since `start` (a StopwatchClock::now() taken earlier).
inline double secondsSince(StopwatchClock::time_point start)
{
    return std::chrono::duration<double>(StopwatchClock::now() - start).count();
}

}  // namespace ngi
