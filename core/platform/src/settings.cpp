#include "rayspace/settings.h"

#include "rayspace/error.h"

namespace rayspace {
namespace {

const Settings kDefaults{};
// The settings in force on this thread; nullptr: kDefaults. Thread-local by design: it is how a
// scope's settings reach the code it calls without being process-wide.
thread_local const Settings* tls_settings = nullptr;

void Check(const Settings& s) {
  RS_CHECK_MSG(s.threads >= 0, "thread count {} is negative", s.threads);
  RS_CHECK_MSG(s.local_size >= 1 && s.local_size <= 1024, "workgroup local size {} out of range [1, 1024]", s.local_size);
  RS_CHECK_MSG(s.subgroup_size >= 1 && s.subgroup_size <= 128 && (s.subgroup_size & (s.subgroup_size - 1)) == 0,
               "subgroup size {} is not a power of two in [1, 128]", s.subgroup_size);
}

}  // namespace

const Settings& CurrentSettings() { return tls_settings ? *tls_settings : kDefaults; }

ScopedSettings::ScopedSettings(Settings settings) : settings_(std::move(settings)), outer_(tls_settings) {
  Check(settings_);
  tls_settings = &settings_;
}

ScopedSettings::~ScopedSettings() { tls_settings = outer_; }

SettingsInForce::SettingsInForce(const Settings& settings) : outer_(tls_settings) { tls_settings = &settings; }
SettingsInForce::~SettingsInForce() { tls_settings = outer_; }

}  // namespace rayspace
