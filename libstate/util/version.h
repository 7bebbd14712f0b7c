// Library version (semantic versioning), for provenance records and --version.
#pragma once

namespace hapstate {
const char* version_string();
}
