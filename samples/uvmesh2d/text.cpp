#include "uvmesh2d/text.h"

#include <cctype>
#include <charconv>
#include <cmath>
#include <system_error>

namespace uvmesh::cli2d::text {

std::optional<std::int64_t> parse_int(std::string_view s) {
  if (!s.empty() && s.front() == '+') s.remove_prefix(1);  // from_chars rejects '+'
  std::int64_t v = 0;
  auto [p, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (ec != std::errc() || p != s.data() + s.size() || s.empty()) return std::nullopt;
  return v;
}

std::optional<double> parse_double(std::string_view s) {
  if (!s.empty() && s.front() == '+') s.remove_prefix(1);
  if (s.empty()) return std::nullopt;
  double v = 0;
  auto [p, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  // result_out_of_range: "1e999" and denormal underflow. Overflow becomes +-inf so that the
  // caller's "not finite" message applies; underflow is harmless and kept as parsed.
  if (ec == std::errc::result_out_of_range && p == s.data() + s.size()) {
    bool neg = s.front() == '-';
    std::size_t e = s.find_first_of("eE");
    bool big_exponent = e != std::string_view::npos && e + 1 < s.size() && s[e + 1] != '-';
    if (big_exponent) return neg ? -HUGE_VAL : HUGE_VAL;
    return 0.0;
  }
  if (ec != std::errc() || p != s.data() + s.size()) return std::nullopt;
  return v;
}

static bool is_space(char c) {
  return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f';
}

bool LineReader::next(std::vector<std::string_view>& fields) {
  while (std::getline(in_, buf_)) {
    ++line_;
    std::size_t hash = buf_.find('#');
    if (hash != std::string::npos) buf_.resize(hash);
    fields.clear();
    std::size_t i = 0, n = buf_.size();
    while (i < n) {
      while (i < n && is_space(buf_[i])) ++i;
      std::size_t j = i;
      while (j < n && !is_space(buf_[j])) ++j;
      if (j > i) fields.emplace_back(buf_.data() + i, j - i);
      i = j;
    }
    if (!fields.empty()) return true;
  }
  return false;
}

bool TokenReader::fill() {
  if (!std::getline(in_, buf_)) return false;
  ++line_;
  std::size_t hash = buf_.find('#');
  if (hash != std::string::npos) buf_.resize(hash);
  pos_ = 0;
  have_line_ = true;
  return true;
}

bool TokenReader::next(std::string& token) {
  for (;;) {
    if (have_line_) {
      while (pos_ < buf_.size() && is_space(buf_[pos_])) ++pos_;
      if (pos_ < buf_.size()) {
        std::size_t j = pos_;
        while (j < buf_.size() && !is_space(buf_[j])) ++j;
        token.assign(buf_, pos_, j - pos_);
        pos_ = j;
        return true;
      }
    }
    if (!fill()) return false;
  }
}

void append_double(std::string& out, double v) {
  char buf[32];
  auto r = std::to_chars(buf, buf + sizeof buf, v);
  out.append(buf, r.ptr);
}

void append_fixed(std::string& out, double v, int decimals) {
  char buf[64];
  auto r = std::to_chars(buf, buf + sizeof buf, v, std::chars_format::fixed, decimals);
  if (r.ec != std::errc()) {  // |v| too large for the buffer: fall back to shortest form
    append_double(out, v);
    return;
  }
  std::string_view s(buf, static_cast<std::size_t>(r.ptr - buf));
  if (s == "-0" || s.find_first_not_of("-0.") == std::string_view::npos) s = "0";  // no "-0.0"
  out.append(s);
}

void append_int(std::string& out, std::int64_t v) {
  char buf[24];
  auto r = std::to_chars(buf, buf + sizeof buf, v);
  out.append(buf, r.ptr);
}

std::string extension(std::string_view path) {
  std::size_t slash = path.find_last_of('/');
  std::string_view name = slash == std::string_view::npos ? path : path.substr(slash + 1);
  std::size_t dot = name.find_last_of('.');
  if (dot == std::string_view::npos || dot == 0) return {};
  std::string e(name.substr(dot));
  for (char& c : e) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return e;
}

std::string quoted(std::string_view s) {
  static constexpr char kHex[] = "0123456789abcdef";
  std::string q = "'";
  for (const char ch : s.substr(0, 40)) {
    const auto b = static_cast<unsigned char>(ch);
    if (b >= 0x20 && b < 0x7f) {
      q += ch;
    } else {
      q += "\\x";
      q += kHex[b >> 4];
      q += kHex[b & 15];
    }
  }
  if (s.size() > 40) q += "...";
  return q + "'";
}

}  // namespace uvmesh::cli2d::text
