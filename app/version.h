// `rayspace --version`: the version, the commit it was built from, the backends built in and the
// libraries (with the versions their headers declare) it was built against.
#pragma once
#include <string>

namespace rayspace::app {

std::string VersionText();

}  // namespace rayspace::app
