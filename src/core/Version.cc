// levelfuse: version string.

#include <levelfuse/Version.h>

namespace levelfuse {
const char* version() { return LEVELFUSE_VERSION_STRING; }
}  // namespace levelfuse
