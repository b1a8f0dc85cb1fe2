// Files that appear under their final name only when complete: a temporary
// file beside the destination, synced, then given the name without
// replacing (RENAME_NOREPLACE, or link(2) where the file system lacks it)
// or, when asked, replacing atomically; the directory is synced after.
// Used by the online backup and the restore (docs/operations.md, Backup).
#pragma once

// Header-only: storage/CMakeLists.txt names the backend's sources one by
// one, and these few calls are shared by database.cc and sqlite_storage.cc.
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

#include "core/status.h"

namespace thermocomp::durable {

inline std::string ErrnoText() {
  return std::strerror(errno);
}

inline std::string DirectoryOf(const std::string& path) {
  const size_t slash = path.rfind('/');
  if (slash == std::string::npos) return ".";
  return slash == 0 ? "/" : path.substr(0, slash);
}

inline bool Exists(const std::string& path) {
  struct stat st {};
  return lstat(path.c_str(), &st) == 0;
}

// The size of a regular file, or -1 when it is missing or not regular.
inline int64_t RegularFileSize(const std::string& path) {
  struct stat st {};
  if (stat(path.c_str(), &st) != 0 || !S_ISREG(st.st_mode)) return -1;
  return st.st_size;
}

// Removes `path` if it exists; a missing file is fine.
inline void RemoveIfPresent(const std::string& path) {
  (void)unlink(path.c_str());
}

// A new empty file in `dest`'s directory, named after it
// (".<name>.<tag>-XXXXXX"), for the caller to fill and then Publish.
inline StatusOr<std::string> MakeTemporaryBeside(const std::string& dest, const std::string& tag) {
  const size_t slash = dest.rfind('/');
  const std::string name = slash == std::string::npos ? dest : dest.substr(slash + 1);
  std::string tmp = DirectoryOf(dest) + "/." + name + "." + tag + "-XXXXXX";
  const int fd = mkostemp(tmp.data(), O_CLOEXEC);
  if (fd < 0) {
    return Status::Unavailable("cannot create a file in " + DirectoryOf(dest) + ": " + ErrnoText());
  }
  close(fd);
  return tmp;
}

// fsync of a file's data (by path).
inline Status SyncFile(const std::string& path) {
  const int fd = open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) return Status::Unavailable("cannot open " + path + ": " + ErrnoText());
  const int rc = fsync(fd);
  const std::string why = rc == 0 ? "" : ErrnoText();
  close(fd);
  if (rc != 0) return Status::Unavailable("cannot sync " + path + ": " + why);
  return Status::Ok();
}

// fsync of the directory holding `path`, so a rename or unlink in it lasts.
inline Status SyncDirectoryOf(const std::string& path) {
  const std::string dir = DirectoryOf(path);
  const int fd = open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd < 0) return Status::Unavailable("cannot open directory " + dir + ": " + ErrnoText());
  const int rc = fsync(fd);
  close(fd);
  if (rc != 0) return Status::Unavailable("cannot sync directory " + dir);
  return Status::Ok();
}

// Links `existing` under the new name `name`, never over an existing file.
inline Status LinkNew(const std::string& existing, const std::string& name) {
  if (link(existing.c_str(), name.c_str()) == 0) return Status::Ok();
  if (errno == EEXIST) return Status::Conflict(name + " already exists");
  return Status::Unavailable("cannot link " + existing + " to " + name + ": " + ErrnoText());
}

// Gives `tmp` the name `dest`: never over an existing file unless `replace`
// (then atomically). On success `tmp` no longer exists; on failure it is
// left for the caller to remove.
inline Status Publish(const std::string& tmp, const std::string& dest, bool replace) {
  if (replace) {
    if (rename(tmp.c_str(), dest.c_str()) != 0) {
      return Status::Unavailable("cannot rename " + tmp + " to " + dest + ": " + ErrnoText());
    }
  } else if (renameat2(AT_FDCWD, tmp.c_str(), AT_FDCWD, dest.c_str(), RENAME_NOREPLACE) != 0) {
    if (errno == EEXIST) return Status::Conflict(dest + " already exists");
    if (errno != EINVAL && errno != ENOSYS) {
      return Status::Unavailable("cannot rename " + tmp + " to " + dest + ": " + ErrnoText());
    }
    // A file system without RENAME_NOREPLACE: link(2) refuses an existing
    // name just the same.
    if (Status s = LinkNew(tmp, dest); !s.ok()) return s;
    RemoveIfPresent(tmp);
  }
  return SyncDirectoryOf(dest);
}

// Copies the bytes of `from` into the existing file `to` (truncating it).
inline Status CopyBytes(const std::string& from, const std::string& to) {
  const int in = open(from.c_str(), O_RDONLY | O_CLOEXEC);
  if (in < 0) return Status::NotFound("cannot read " + from + ": " + ErrnoText());
  const int out = open(to.c_str(), O_WRONLY | O_TRUNC | O_CLOEXEC);
  if (out < 0) {
    close(in);
    return Status::Unavailable("cannot write " + to + ": " + ErrnoText());
  }
  Status result = Status::Ok();
  char buf[1 << 16];
  for (;;) {
    const ssize_t n = read(in, buf, sizeof buf);
    if (n == 0) break;
    if (n < 0) {
      if (errno == EINTR) continue;
      result = Status::Unavailable("cannot read " + from + ": " + ErrnoText());
      break;
    }
    ssize_t done = 0;
    while (done < n) {
      const ssize_t w = write(out, buf + done, static_cast<size_t>(n - done));
      if (w < 0 && errno == EINTR) continue;
      if (w < 0) {
        result = Status::InsufficientStorage("cannot write " + to + ": " + ErrnoText());
        break;
      }
      done += w;
    }
    if (!result.ok()) break;
  }
  close(in);
  close(out);
  return result;
}

}  // namespace thermocomp::durable
