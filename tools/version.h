#pragma once

namespace nfrc {

// Program version written into every output file.
inline constexpr const char* kNfrcVersion = "0.1.0";

}  // namespace nfrc
