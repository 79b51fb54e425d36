// The process's peak resident memory (Linux: VmHWM), and resetting it so that one part of a run can
// be measured on its own.
#pragma once
#include <cstddef>

namespace rayspace::app {

// Returns freed heap memory to the system, then resets the kernel's peak-RSS counter to the current
// resident size (writes 5 to /proc/self/clear_refs, Linux 4.0 and later). False when the counter
// could not be reset: the peak is then the whole process's so far.
bool ResetPeakRss();

// The peak resident set size in bytes since the process started or the last ResetPeakRss: VmHWM from
// /proc/self/status, else getrusage's ru_maxrss (never reset); 0 when neither can be read.
std::size_t PeakRssBytes();

// The resident set size in bytes now (VmRSS); 0 when it cannot be read.
std::size_t CurrentRssBytes();

}  // namespace rayspace::app
