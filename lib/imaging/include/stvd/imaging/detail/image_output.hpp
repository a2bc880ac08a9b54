// Writing a file of the imaging adapter or the ITK file I/O atomically, with
// ImageIoError as its exception (not part of the supported API).
#pragma once

#include <functional>
#include <string>

namespace stvd::imaging::detail {

/// Runs `write` as one atomic output at `path` (files::writeAtomically),
/// with its failures as ImageIoError, the adapter's exception.
void writeAtomically(const std::string& path, const std::function<void(const std::string&)>& write);

}  // namespace stvd::imaging::detail
