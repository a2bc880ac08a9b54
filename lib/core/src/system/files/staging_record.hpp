// The record each staging folder holds of the process that made it, so that
// the folder a run killed with SIGKILL (or by the OOM killer) left behind can
// be told from everything else and removed: only a folder that is
// demonstrably ours - our name, our user, and this record, written by us,
// naming a process that no longer exists - is ever removed. A process is
// identified by its id together with its start time, on this boot of this
// kernel and in this pid namespace, since output folders may lie on a file
// system shared by several machines (NFS) and process ids are reused.
// Private to the files module.
#pragma once

#include <string>

namespace stvd::files::detail {

/// The record's name inside a staging folder (an output may not be named
/// so).
inline constexpr const char* kStagingRecordName = ".stvd-staging-owner";

/// Writes the record of this process into `folder`, a staging folder it has
/// just made (O_EXCL, no link followed). Returns an empty string, or the
/// problem.
std::string writeStagingRecord(const std::string& folder);

/// True when `folder`, an entry named `name` of a folder being swept, is a
/// staging folder of ours whose process is gone: `name` is
/// ".stvd-staging-<pid>-<n>", it is a folder (not a link) owned by this
/// user, it holds a record owned by this user whose pid is the name's, made
/// on this boot of this kernel, in this pid namespace, on this host, and
/// that process has ended (no process of that id, one started at another
/// time, or a zombie). Anything else - a folder without a record (another
/// program's, or an older stvd's), one of another machine or boot, a live
/// process's - is false.
bool isAbandonedStagingFolder(const std::string& folder, const std::string& name);

}  // namespace stvd::files::detail
