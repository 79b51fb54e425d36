// A test's own settings, for the tests beside the libraries and the Vulkan passes alike.
#pragma once
#include "rayspace/settings.h"

namespace rayspace::test {

// A test's own settings (rayspace/settings.h): a copy of those in force, put in force on this thread
// from construction to the end of the scope and edited in place through ->, so that a test changes
// the schedule, sizes, faults or ISA for itself alone and nothing outlives it.
class TestSettings {
 public:
  TestSettings() : settings_(CurrentSettings()), in_force_(settings_) {}
  Settings* operator->() { return &settings_; }
  Settings& operator*() { return settings_; }

 private:
  Settings settings_;
  SettingsInForce in_force_;
};

}  // namespace rayspace::test
