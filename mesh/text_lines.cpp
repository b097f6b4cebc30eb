#include "mesh/text_lines.h"

#include <charconv>
#include <cmath>
#include <cstdint>

#include "mesh/errors.h"
#include "mesh/input_file.h"

namespace pb {
namespace {

bool IsBlank(char c) { return c == ' ' || c == '\t' || c == '\v' || c == '\f'; }

// text[at..], less the blanks at either end.
std::string TrimmedFrom(const std::string& text, size_t at) {
  const size_t from = text.find_first_not_of(" \t\v\f", at);
  return from == std::string::npos ? std::string() : text.substr(from, text.find_last_not_of(" \t\v\f") + 1 - from);
}

void AppendUtf8(std::string& out, uint32_t code) {
  if (code < 0x80) {
    out.push_back(char(code));
  } else if (code < 0x800) {
    out.push_back(char(0xC0 | (code >> 6)));
    out.push_back(char(0x80 | (code & 0x3F)));
  } else if (code < 0x10000) {
    out.push_back(char(0xE0 | (code >> 12)));
    out.push_back(char(0x80 | ((code >> 6) & 0x3F)));
    out.push_back(char(0x80 | (code & 0x3F)));
  } else {
    out.push_back(char(0xF0 | (code >> 18)));
    out.push_back(char(0x80 | ((code >> 12) & 0x3F)));
    out.push_back(char(0x80 | ((code >> 6) & 0x3F)));
    out.push_back(char(0x80 | (code & 0x3F)));
  }
}

// UTF-16 (after its byte order mark) to UTF-8. A lone surrogate becomes U+FFFD; an odd last byte is dropped.
std::string Utf16ToUtf8(const std::string& bytes, bool bigEndian) {
  std::string out;
  out.reserve(bytes.size() / 2);
  const auto unit = [&](size_t i) {
    const uint32_t a = uint8_t(bytes[i]), b = uint8_t(bytes[i + 1]);
    return bigEndian ? (a << 8 | b) : (b << 8 | a);
  };
  for (size_t i = 2; i + 1 < bytes.size(); i += 2) {
    uint32_t code = unit(i);
    if (code >= 0xD800 && code < 0xDC00 && i + 3 < bytes.size() && unit(i + 2) >= 0xDC00 && unit(i + 2) < 0xE000) {
      code = 0x10000 + ((code - 0xD800) << 10) + (unit(i + 2) - 0xDC00);
      i += 2;
    } else if (code >= 0xD800 && code < 0xE000) {
      code = 0xFFFD;
    }
    AppendUtf8(out, code);
  }
  return out;
}

std::string DecodeText(std::string bytes) {
  if (bytes.size() >= 2 && uint8_t(bytes[0]) == 0xFE && uint8_t(bytes[1]) == 0xFF) return Utf16ToUtf8(bytes, true);
  if (bytes.size() >= 2 && uint8_t(bytes[0]) == 0xFF && uint8_t(bytes[1]) == 0xFE) return Utf16ToUtf8(bytes, false);
  if (bytes.rfind("\xEF\xBB\xBF", 0) == 0) bytes.erase(0, 3);
  return bytes;
}

template <typename T>
T ParseNumber(const TextLine& line, size_t i) {
  const std::string& t = line.tokens[i];
  const char* begin = t.data() + (t.size() > 1 && t[0] == '+');  // from_chars refuses a leading '+'.
  T value = 0;
  const auto [end, ec] = std::from_chars(begin, t.data() + t.size(), value);
  if (ec != std::errc() || end != t.data() + t.size())
    line.Fail("malformed number '" + t + "' in '" + line.Keyword() + "'");
  if (!std::isfinite(value)) line.Fail("non-finite number '" + t + "' in '" + line.Keyword() + "'");
  return value;
}

}  // namespace

void TextLine::Fail(const std::string& message) const { throw InputError(*file, number, message); }

std::string TextLine::Warning(const std::string& message) const {
  return *file + ":" + std::to_string(number) + ": warning: " + message;
}

void TextLine::ExpectValues(size_t atLeast, size_t atMost) const {
  const size_t n = ValueCount();
  if (n < atLeast || n > atMost)
    Fail("'" + Keyword() + "' takes " +
         (atLeast == atMost ? std::to_string(atLeast) : std::to_string(atLeast) + " to " + std::to_string(atMost)) +
         " values, found " + std::to_string(n));
}

float TextLine::Number(size_t i) const { return ParseNumber<float>(*this, i); }
double TextLine::Double(size_t i) const { return ParseNumber<double>(*this, i); }

std::string TextLine::JoinValues(size_t first) const {
  std::string s;
  for (size_t i = first; i < tokens.size(); ++i) s += (i > first ? " " : "") + tokens[i];
  return s;
}

TextFileReader::TextFileReader(const std::string& path, const std::string& what)
    : path_(path), text_(DecodeText(ReadRegularFile(path, what))) {}

bool TextFileReader::NextPhysicalLine(std::string& text) {
  if (at_ >= text_.size()) return false;
  const size_t end = text_.find_first_of("\r\n", at_);
  const size_t stop = end == std::string::npos ? text_.size() : end;
  text.assign(text_, at_, stop - at_);
  at_ = stop;
  if (at_ < text_.size() && text_[at_++] == '\r' && at_ < text_.size() && text_[at_] == '\n') ++at_;  // CRLF
  ++number_;
  if (text.find('\0') != std::string::npos) throw InputError(path_, number_, "a NUL byte: this is not a text file");
  return true;
}

bool TextFileReader::Next(TextLine& line) {
  // `line` and the reader's line_ keep their memory from statement to statement: a 400,000-line OBJ had paid
  // several allocations per line.
  std::string& text = line_;
  while (NextPhysicalLine(text)) {
    const int first = number_;
    // A trailing backslash continues the statement on the next line.
    for (std::string more;;) {
      size_t last = text.find_last_not_of(" \t\v\f");
      if (last == std::string::npos || text[last] != '\\' || !NextPhysicalLine(more)) break;
      text.resize(last);
      text += ' ' + more;
    }
    if (const size_t hash = text.find('#'); hash != std::string::npos) text.resize(hash);
    line.file = &path_, line.number = first, line.rest.clear();
    size_t count = 0;
    for (size_t i = 0; i < text.size();) {
      while (i < text.size() && IsBlank(text[i])) ++i;
      const size_t start = i;
      while (i < text.size() && !IsBlank(text[i])) ++i;
      if (i == start) continue;
      if (count == line.tokens.size()) line.tokens.emplace_back();
      line.tokens[count++].assign(text, start, i - start);
      if (count == 1) line.rest = TrimmedFrom(text, i);
    }
    line.tokens.resize(count);
    if (count > 0) return true;
  }
  return false;
}

std::vector<std::string> SplitEscaped(const std::string& text) {
  std::vector<std::string> parts;
  std::string current;
  for (size_t i = 0; i < text.size(); ++i) {
    if (text[i] == '\\' && i + 1 < text.size() && IsBlank(text[i + 1])) {
      current.push_back(text[++i]);
    } else if (IsBlank(text[i])) {
      if (!current.empty()) parts.push_back(current);
      current.clear();
    } else {
      current.push_back(text[i]);
    }
  }
  if (!current.empty()) parts.push_back(current);
  return parts;
}

void WarningLog::Add(const std::string& kind, const std::string& message) {
  if (const auto it = index_.find(kind); it != index_.end()) {
    ++entries_[it->second].count;
  } else if (entries_.size() < kMaxKinds) {
    index_.emplace(kind, entries_.size());
    entries_.push_back({kind, message, 1});
  } else {
    ++others_;
  }
}

std::vector<std::string> WarningLog::Lines() const {
  std::vector<std::string> lines;
  for (const Entry& e : entries_)
    lines.push_back(e.count > 1 ? e.first + " (" + std::to_string(e.count) + " in all)" : e.first);
  if (others_ > 0)
    lines.push_back("warning: " + std::to_string(others_) + " more warnings of " + "other kinds, not listed");
  return lines;
}

size_t WarningLog::Count(const std::string& kind) const {
  const auto it = index_.find(kind);
  return it == index_.end() ? 0 : entries_[it->second].count;
}

}  // namespace pb
