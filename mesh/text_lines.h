// The text files of a scene (OBJ, MTL) as other programs write them, read statement by statement with the
// location of each for messages; and the warnings a loader collects, one per kind, counted.
//
// A statement is one line, split into tokens at blanks (space, tab, vertical tab, form feed):
//   - lines end at LF, CRLF or a lone CR (old Mac exporters);
//   - a line whose last non-blank character is '\' continues on the next (the OBJ spec's line continuation);
//     the statement keeps the number of its first line;
//   - '#' starts a comment, to the end of the line;
//   - a UTF-8 byte order mark is skipped; a file that starts with a UTF-16 byte order mark (big or little endian,
//     as some Windows tools write) is decoded to UTF-8 first;
//   - a NUL byte, after any UTF-16 decoding, is refused: this is not a text file.
// Only regular files are read (mesh/input_file.h).
#pragma once

#include <cstddef>
#include <string>
#include <unordered_map>
#include <vector>

namespace pb {

// One statement of a text file: its keyword and values, and where it is.
struct TextLine {
  const std::string* file = nullptr;
  int number = 0;                    // 1-based line number of its first line
  std::vector<std::string> tokens;   // tokens[0] is the keyword
  std::string rest;                  // the text after the keyword, trimmed, with its inner blanks as written

  const std::string& Keyword() const { return tokens[0]; }
  size_t ValueCount() const { return tokens.size() - 1; }
  // InputError "file:line: error: message".
  [[noreturn]] void Fail(const std::string& message) const;
  // "file:line: warning: message".
  std::string Warning(const std::string& message) const;
  // InputError unless it has atLeast..atMost values.
  void ExpectValues(size_t atLeast, size_t atMost) const;
  // Value i (1-based) as a finite number; InputError naming it when malformed or not finite.
  float Number(size_t i) const;
  double Double(size_t i) const;
  // The values joined by single spaces: a name as written, whatever blanks separate its words.
  std::string Name() const { return JoinValues(1); }
  std::string JoinValues(size_t first) const;
};

// Reads a text file statement by statement (see the top of this file).
class TextFileReader {
 public:
  // `what` names the file in messages ("scene file", "material library"). InputError when it cannot be read.
  TextFileReader(const std::string& path, const std::string& what);
  // The next statement that has a keyword; false at the end of the file.
  bool Next(TextLine& line);
  // How far the reading has come, and the whole, in bytes of the decoded text.
  size_t Position() const { return at_; }
  size_t Size() const { return text_.size(); }

 private:
  bool NextPhysicalLine(std::string& text);

  std::string path_;
  std::string text_;  // the whole file, as UTF-8
  std::string line_;  // the statement being split, kept to reuse its memory
  size_t at_ = 0;
  int number_ = 0;
};

// Splits `text` at blanks that are not escaped by a backslash, and unescapes "\ " to a blank: how OBJ files name
// files with spaces on an 'mtllib' line ("invalid\ file.mtl").
std::vector<std::string> SplitEscaped(const std::string& text);

// The warnings of one load. Only the first warning of each kind is kept in full; later ones of that kind are
// counted, so a file with 10,000 zero-area triangles says so in one line. At most kMaxKinds kinds are kept; the
// warnings of any further kind are counted together in one last line, so that a hostile file of a million
// distinct unknown keywords costs neither time nor memory.
class WarningLog {
 public:
  static constexpr size_t kMaxKinds = 64;
  // `kind` groups warnings ("zero-area triangle"); `message` is the full "file:line: warning: ..." text.
  void Add(const std::string& kind, const std::string& message);
  // One line per kind, in the order each kind first appeared; "(N in all)" is appended where N > 1.
  std::vector<std::string> Lines() const;
  size_t Count(const std::string& kind) const;

 private:
  struct Entry {
    std::string kind, first;
    size_t count = 0;
  };
  std::vector<Entry> entries_;
  std::unordered_map<std::string, size_t> index_;  // kind -> its entry
  size_t others_ = 0;                              // warnings of kinds beyond kMaxKinds
};

}  // namespace pb
