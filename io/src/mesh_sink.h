// Private to uvmesh::io's mesh writers: the buffered output (Sink, Record, the binary
// byte orders) and the grouping of nodes and elements by entity that every format
// family uses (mesh_writer.cpp, mesh_writer_gmsh.cpp, mesh_writer_formats.cpp).
//
// Output goes through one fixed buffer (Sink) filled with std::to_chars and handed to
// write(2) in 1 MiB chunks: meshes reach millions of triangles, and a stream insertion
// per number is several times slower than this for the same bytes.
#pragma once

#include <unistd.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cerrno>
#include <charconv>
#include <cstdint>
#include <cstring>
#include <initializer_list>
#include <memory>
#include <string_view>
#include <vector>

#include "uvmesh/geom/types.h"

namespace uvmesh::io::detail {

// ----------------------------------------------------------------------------- output

// Every format here numbers nodes and entities from 1 (Gmsh tags, Medit and OBJ indices).
template <class Index>
constexpr std::int64_t one_based(Index index) {
  return static_cast<std::int64_t>(index) + 1;
}

// Buffered writer on a file descriptor. It never throws and never prints: the first
// failing write(2) is remembered in error() and every later call is a no-op, so format
// writers can run straight through and the caller checks once at the end.
class Sink {
 public:
  explicit Sink(int fd) : fd_(fd), buf_(new char[kCap]) {}

  int error() const { return err_; }

  void put(std::string_view s) {
    if (s.size() > kCap) {
      flush();
      write_all(s.data(), s.size());
      return;
    }
    room(s.size());
    std::memcpy(buf_.get() + pos_, s.data(), s.size());
    pos_ += s.size();
  }
  void put(char c) {
    room(1);
    buf_[pos_++] = c;
  }
  // Shortest decimal form that reads back to the same double (std::to_chars without a
  // precision), i.e. as exact as %.17g and usually much shorter.
  void num(double v) {
    room(kNumMax);
    pos_ = static_cast<std::size_t>(std::to_chars(buf_.get() + pos_, buf_.get() + kCap, v).ptr -
                                    buf_.get());
  }
  void num(std::int64_t v) {
    room(kNumMax);
    pos_ = static_cast<std::size_t>(std::to_chars(buf_.get() + pos_, buf_.get() + kCap, v).ptr -
                                    buf_.get());
  }
  void num(int v) { num(static_cast<std::int64_t>(v)); }
  void num(std::size_t v) { num(static_cast<std::int64_t>(v)); }
  // Integers separated by spaces, then a newline: the count and block-header lines.
  void line(std::initializer_list<std::int64_t> values) {
    const char* sep = "";
    for (std::int64_t v : values) {
      put(sep);
      num(v);
      sep = " ";
    }
    put('\n');
  }
  // "x y z", the common record part.
  void xyz(const geom::Vec3& p) {
    num(p.x);
    put(' ');
    num(p.y);
    put(' ');
    num(p.z);
  }
  void raw(const void* p, std::size_t n) { put(std::string_view(static_cast<const char*>(p), n)); }

  // Hands the buffer to the kernel. Also called by room() when full.
  void flush() {
    if (pos_ > 0) write_all(buf_.get(), pos_);
    pos_ = 0;
  }

 private:
  static constexpr std::size_t kCap = std::size_t{1} << 20;
  static constexpr std::size_t kNumMax = 32;  // longest to_chars output of a double is 24

  void room(std::size_t n) {
    if (pos_ + n > kCap) flush();
  }
  void write_all(const char* p, std::size_t n) {
    while (n > 0 && err_ == 0) {
      const ssize_t w = ::write(fd_, p, n);
      if (w < 0) {
        if (errno == EINTR) continue;
        err_ = errno;
      } else if (w == 0) {
        err_ = EIO;  // no progress and no errno: do not spin
      } else {
        p += w;
        n -= static_cast<std::size_t>(w);
      }
    }
  }

  int fd_;
  std::unique_ptr<char[]> buf_;
  std::size_t pos_ = 0;
  int err_ = 0;
};

// Binary numbers in a fixed byte order, whatever the host's.
template <class T>
void put_le(Sink& out, T v) {
  auto bits = std::bit_cast<std::array<unsigned char, sizeof(T)>>(v);
  if constexpr (std::endian::native == std::endian::big) std::reverse(bits.begin(), bits.end());
  out.raw(bits.data(), bits.size());
}

template <class T>
void put_be(Sink& out, T v) {
  auto bits = std::bit_cast<std::array<unsigned char, sizeof(T)>>(v);
  if constexpr (std::endian::native == std::endian::little) std::reverse(bits.begin(), bits.end());
  out.raw(bits.data(), bits.size());
}

// The numbers of a record in .msh 4.1 (and other formats with an ASCII and a binary
// form of the same records): ASCII separates them with spaces and ends the record with a
// newline; binary writes them little-endian back to back (Gmsh's binary files are in the
// writer's byte order, and it reads the endianness marker 1 written in $MeshFormat).
class Record {
 public:
  Record(Sink& out, bool binary) : out_(out), binary_(binary) {}
  bool binary() const { return binary_; }
  Record& i(std::int64_t v) {  // a C int (tags, dims, types)
    if (binary_)
      put_le(out_, static_cast<std::int32_t>(v));
    else
      text(v);
    return *this;
  }
  Record& z(std::int64_t v) {  // a size_t (counts, node and element tags)
    if (binary_)
      put_le(out_, static_cast<std::uint64_t>(v));
    else
      text(v);
    return *this;
  }
  Record& d(double v) {
    if (binary_)
      put_le(out_, v);
    else
      text(v);
    return *this;
  }
  Record& xyz(const geom::Vec3& p) { return d(p.x).d(p.y).d(p.z); }
  void end() {
    if (!binary_) out_.put('\n');
    first_ = true;
  }

 private:
  template <class T>
  void text(T v) {
    if (!first_) out_.put(' ');
    first_ = false;
    out_.num(v);
  }
  Sink& out_;
  bool binary_;
  bool first_ = true;
};

// ----------------------------------------------------------------------------- grouping

// Stable counting sort of items 0..n-1 by a dense key in [0, num_keys): order lists the
// items key by key (each key's items in their original order), and the items of key k
// are order[first[k]] .. order[first[k+1]-1]. Used to group nodes by entity and elements
// by edge or face in O(n), keeping the mesh's own order within a group.
struct Buckets {
  std::vector<std::size_t> first;
  std::vector<std::int32_t> order;
  std::size_t size(std::size_t k) const { return first[k + 1] - first[k]; }
  template <class F>
  void each(std::size_t k, F f) const {
    for (std::size_t i = first[k]; i < first[k + 1]; ++i) f(static_cast<std::size_t>(order[i]));
  }
};

template <class KeyFn>
Buckets bucket(std::size_t n, std::size_t num_keys, KeyFn key) {
  Buckets b;
  b.first.assign(num_keys + 1, 0);
  for (std::size_t i = 0; i < n; ++i) ++b.first[key(i) + 1];
  for (std::size_t k = 0; k < num_keys; ++k) b.first[k + 1] += b.first[k];
  std::vector<std::size_t> next(b.first.begin(), b.first.end() - 1);
  b.order.resize(n);
  for (std::size_t i = 0; i < n; ++i) b.order[next[key(i)]++] = static_cast<std::int32_t>(i);
  return b;
}

// ----------------------------------------------------------------------------- entity counts

// Entity counts of the mesh: one past the largest id of each kind it mentions, at least
// the model's counts when there is a model.
struct Counts {
  std::size_t vertices = 0, edges = 0, faces = 0;
};

}  // namespace uvmesh::io::detail
