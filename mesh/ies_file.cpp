#include "mesh/ies_file.h"

#include <fmt/format.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <numbers>

#include "mesh/errors.h"
#include "mesh/text_lines.h"

namespace pb {
namespace {

constexpr double kMostCandela = 1e30;  // [cd], as the lights file bounds an intensity

// The numbers after the TILT= line, each with its line, read one by one.
class NumberStream {
 public:
  explicit NumberStream(const std::string& path) : path_(path) {}

  void AddLine(const TextLine& line) {
    for (const std::string& token : line.tokens) {
      for (size_t at = 0; at <= token.size();) {
        const size_t comma = std::min(token.find(',', at), token.size());
        if (comma > at) words_.push_back({token.substr(at, comma - at), line.number});
        at = comma + 1;
      }
    }
  }

  size_t Remaining() const { return words_.size() - next_; }

  // The next number, `what` naming it in messages.
  double Next(const std::string& what) {
    if (next_ == words_.size())
      throw InputError(path_, words_.empty() ? 0 : words_.back().line, "the file ends before its " + what);
    const Word& w = words_[next_++];
    double value = 0;
    const char* begin = w.text.data() + (w.text.size() > 1 && w.text[0] == '+');
    const auto [end, ec] = std::from_chars(begin, w.text.data() + w.text.size(), value);
    if (ec != std::errc() || end != w.text.data() + w.text.size()) Fail("malformed number '" + w.text + "' for the " + what);
    if (!std::isfinite(value)) Fail("non-finite number '" + w.text + "' for the " + what);
    return value;
  }

  // The next number as a count in [least, most], and no more than the numbers left after it can fill.
  size_t Count(const std::string& what, size_t least, size_t most) {
    const double n = Next(what);
    if (!(n >= double(least) && n <= double(most) && n == std::floor(n)))
      Fail(fmt::format("the {} must be a whole number in [{}, {}], not {:g}", what, least, most, n));
    return size_t(n);
  }

  // `count` numbers, each within [lo, hi].
  std::vector<double> Many(size_t count, const std::string& what, double lo, double hi) {
    if (count > Remaining())
      throw InputError(path_, words_.empty() ? 0 : words_.back().line,
                       fmt::format("the file ends after {} of its {} {}", Remaining(), count, what));
    std::vector<double> values(count);
    for (double& v : values) {
      v = Next(what);
      if (!(v >= lo && v <= hi)) Fail(fmt::format("{} must lie in [{:g}, {:g}], not {:g}", what, lo, hi, v));
    }
    return values;
  }

  // InputError at the line of the number read last.
  [[noreturn]] void Fail(const std::string& message) const {
    throw InputError(path_, next_ ? words_[next_ - 1].line : 0, message);
  }

 private:
  struct Word {
    std::string text;
    int line;
  };
  std::string path_;
  std::vector<Word> words_;
  size_t next_ = 0;
};

// Reads past the header to the TILT= line; its value ("NONE", "INCLUDE" or a file name), and the numbers after it.
std::string ReadToTilt(const std::string& path, NumberStream& numbers) {
  TextFileReader reader(path, "IES file");
  TextLine line;
  std::string tilt;
  bool found = false;
  while (reader.Next(line)) {
    if (found) {
      numbers.AddLine(line);
      continue;
    }
    std::string joined;
    for (const std::string& t : line.tokens) joined += t;
    if (joined.rfind("TILT=", 0) == 0) found = true, tilt = joined.substr(5);
  }
  if (!found) throw InputError(path, 0, "no 'TILT=' line: this is not an IES LM-63 photometric file");
  return tilt;
}

// TILT=INCLUDE's table: lamp-to-luminaire geometry (1 to 3), a count, its angles and its factors.
void SkipTiltTable(NumberStream& numbers) {
  numbers.Count("tilt's lamp-to-luminaire geometry", 1, 3);
  const size_t pairs = numbers.Count("tilt's angle count", 0, numbers.Remaining() / 2);
  numbers.Many(pairs, "tilt angles", 0, 180);
  numbers.Many(pairs, "tilt factors", 0, kMostCandela);
}

// The horizontal angles [deg] must be one of LM-63's symmetries.
void CheckHorizontalAngles(const std::vector<double>& c, NumberStream& numbers) {
  const double first = c.front(), last = c.back();
  const bool symmetric = c.size() == 1 ? first == 0
                                       : (first == 0 && (last == 90 || last == 180 || (last > 180 && last <= 360))) ||
                                             (first == 90 && last == 270);
  if (!symmetric)
    numbers.Fail(fmt::format("horizontal angles from {:g} to {:g} degrees: LM-63 allows 0 to 0, 90, 180 or up to 360, "
                             "or 90 to 270", first, last));
}

void CheckIncreasing(const std::vector<double>& radians, const std::string& what, NumberStream& numbers) {
  const auto at = std::adjacent_find(radians.begin(), radians.end(), std::greater_equal<>());
  if (at == radians.end()) return;
  const auto i = size_t(at - radians.begin());
  numbers.Fail(fmt::format("{} must increase: angle {} ({:.17g} degrees) is not above angle {} ({:.17g} degrees) once "
                           "converted to radians", what, i + 2, at[1] * 180 / std::numbers::pi, i + 1,
                           at[0] * 180 / std::numbers::pi));
}

std::vector<double> Radians(std::vector<double> degrees) {
  for (double& d : degrees) d = d / 180 * std::numbers::pi;  // so that 90, 180 and 360 degrees are exact
  return degrees;
}

}  // namespace

IntensityProfile LoadIesFile(const std::string& path) {
  NumberStream numbers(path);
  const std::string tilt = ReadToTilt(path, numbers);
  if (tilt == "INCLUDE") SkipTiltTable(numbers);
  numbers.Next("lamp count");
  numbers.Next("lumens per lamp");
  const double multiplier = numbers.Many(1, "candela multiplier", 0, kMostCandela)[0];
  const size_t vertical = numbers.Count("vertical angle count", 2, numbers.Remaining());
  const size_t horizontal = numbers.Count("horizontal angle count", 1, numbers.Remaining() / vertical);
  const double type = numbers.Next("photometric type");
  if (type != 1)
    numbers.Fail(fmt::format("photometric type {:g}: only type C (1) is read; types B (2) and A (3) are not", type));
  numbers.Next("units type");
  numbers.Many(3, "luminous opening's width, length and height", -kMostCandela, kMostCandela);
  const std::vector<double> factors = numbers.Many(2, "ballast factor and ballast-lamp photometric factor", 0, 1e3);
  numbers.Next("input watts");
  // Checked as the profile holds them, in radians: two angles a rounding apart in degrees may be one in radians.
  const std::vector<double> gamma = Radians(numbers.Many(vertical, "vertical angles", 0, 180));
  CheckIncreasing(gamma, "the vertical angles", numbers);
  const std::vector<double> degrees = numbers.Many(horizontal, "horizontal angles", 0, 360);
  CheckHorizontalAngles(degrees, numbers);
  const std::vector<double> c = Radians(degrees);
  CheckIncreasing(c, "the horizontal angles", numbers);
  std::vector<double> candela = numbers.Many(vertical * horizontal, "candela values", 0, kMostCandela);
  const double scale = multiplier * factors[0] * factors[1];
  for (double& value : candela) value *= scale;
  if (std::any_of(candela.begin(), candela.end(), [](double v) { return !(v <= kMostCandela); }))
    numbers.Fail(fmt::format("the candela multiplier and factors ({:g}) take an intensity past {:g} cd", scale,
                             kMostCandela));
  return IntensityProfile(path, gamma, c, std::move(candela));
}

}  // namespace pb
