// Writing a file's bytes with every failure reported: the text and binary
// writers of the adapters and tools (tables, statistics, streamlines) use it
// instead of streams, whose errors say nothing about their cause.
#pragma once

#include <string>

namespace stvd::files {

/// Creates (or truncates) `path` and writes `bytes` to it, retrying short
/// writes. Throws OutputError naming `path` with the system's reason ("File
/// too large", "No space left on device", ...) when the file cannot be
/// created or not every byte is written, or when closing it fails.
void writeFileContents(const std::string& path, const std::string& bytes);

}  // namespace stvd::files
