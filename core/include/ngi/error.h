// ngi core: the one exception type library code throws.
// Library code never prints or exits (STYLE.md rule 11); the command-line tools catch
// ngi::Error, print its message once and exit non-zero.
#pragma once

#include <stdexcept>
#include <string>

namespace ngi {

// An error with a complete, user-facing message: it names the file (when there is one)
// and the problem, e.g. "bunny.ngi: chunk POS0 fails its CRC32 check".
class Error : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

}  // namespace ngi
