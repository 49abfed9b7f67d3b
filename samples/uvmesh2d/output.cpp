#include "uvmesh2d/output.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>

#include "uvmesh2d/text.h"

namespace uvmesh::cli2d {

std::optional<OutputFormat> output_format(const std::string& path) {
  const std::string e = text::extension(path);
  if (e == ".mesh") return OutputFormat::Medit;
  if (e == ".msh") return OutputFormat::Gmsh22;
  if (e == ".svg") return OutputFormat::Svg;
  return std::nullopt;
}

PendingOutput::PendingOutput(PendingOutput&& o) noexcept
    : dest_(std::move(o.dest_)),
      tmp_(std::move(o.tmp_)),
      out_(std::move(o.out_)),
      committed_(o.committed_) {
  o.tmp_.clear();
  o.committed_ = true;
}

PendingOutput::~PendingOutput() {
  discard();
}

std::optional<Diagnostic> PendingOutput::open(const std::string& dest) {
  dest_ = dest;
  struct stat st {};
  if (::stat(dest.c_str(), &st) == 0 && S_ISDIR(st.st_mode))
    return Diagnostic{dest, 0, "is a directory"};
  // Unique name: pid plus a process-wide counter; O_EXCL makes a clash an error rather
  // than a clobber. Mode 0666 so that the umask applies as for any new file.
  static std::atomic<unsigned> counter{0};
  for (int attempt = 0; attempt < 100; ++attempt) {
    std::string tmp = dest + ".tmp-" + std::to_string(::getpid()) + "-" + std::to_string(counter++);
    int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
    if (fd < 0) {
      if (errno == EEXIST) continue;
      return Diagnostic{dest, 0, std::string("cannot write here: ") + std::strerror(errno)};
    }
    ::close(fd);
    tmp_ = tmp;
    out_.open(tmp_, std::ios::binary | std::ios::trunc);
    if (!out_) {
      discard();
      return Diagnostic{dest, 0, "cannot open a temporary file beside it for writing"};
    }
    committed_ = false;
    return std::nullopt;
  }
  return Diagnostic{dest, 0, "cannot create a unique temporary file beside it"};
}

std::optional<Diagnostic> PendingOutput::commit() {
  if (tmp_.empty()) return Diagnostic{dest_, 0, "internal error: output was not opened"};
  out_.flush();
  const bool good = out_.good();
  out_.close();
  if (!good || out_.fail()) {
    const int err = errno;
    discard();
    return Diagnostic{
        dest_, 0,
        std::string("write failed") + (err ? std::string(": ") + std::strerror(err) : "")};
  }
  if (std::rename(tmp_.c_str(), dest_.c_str()) != 0) {
    const int err = errno;
    discard();
    return Diagnostic{
        dest_, 0,
        std::string("cannot rename the finished temporary file into place: ") + std::strerror(err)};
  }
  tmp_.clear();
  committed_ = true;
  return std::nullopt;
}

void PendingOutput::discard() {
  if (out_.is_open()) out_.close();
  if (!committed_ && !tmp_.empty()) std::remove(tmp_.c_str());
  tmp_.clear();
}

void PendingOutput::undo_commit() {
  if (committed_ && !dest_.empty()) std::remove(dest_.c_str());
  committed_ = false;
}

}  // namespace uvmesh::cli2d
