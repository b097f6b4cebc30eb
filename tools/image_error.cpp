// image_error: relative RMSE of images against a reference, on luminance.
//   image_error REFERENCE.exr IMAGE.exr [IMAGE.exr ...]
// For each image prints "path rmse_relative mean_relative_bias mae_relative max_error_relative
// rmse_smooth_relative", where
//   rmse_relative = sqrt(mean over pixels of (Y - Y_ref)^2) / mean(Y_ref),
//   mae_relative = mean over pixels of |Y - Y_ref| / mean(Y_ref) (less dominated by rare bright pixels),
//   max_error_relative = max over pixels of |Y - Y_ref| / mean(Y_ref), and
//   mean_relative_bias = (mean(Y) - mean(Y_ref)) / mean(Y_ref), with Y the Rec. 709 luminance of radiance, and
//   rmse_smooth_relative = rmse_relative over the pixels away from edges: those whose reference luminance lies
//   within half its own value of each of its four neighbours'. At an edge (a light's outline, an object's) a
//   pixel's error is mostly how its samples fell on either side, the same for any sampler of directions.
// Exit status: 0 on success, 1 for unreadable or mismatched images, 2 for a bad command line.
#include <fmt/core.h>

#include <cmath>
#include <utility>

#include "baker/files/image_io.h"
#include "mesh/errors.h"

int main(int argc, char** argv) {
  if (argc < 3) {
    fmt::print(stderr, "usage: image_error REFERENCE.exr IMAGE.exr [IMAGE.exr ...]\n");
    return 2;
  }
  try {
    const pb::Image reference = pb::ReadExr(argv[1]);
    double referenceMean = 0;
    for (const pb::Rgb& p : reference.pixels) referenceMean += pb::Luminance(p);
    referenceMean /= double(reference.pixels.size());
    const auto smooth = [&](size_t k) {
      const int x = int(k % size_t(reference.width)), y = int(k / size_t(reference.width));
      const double r = pb::Luminance(reference.pixels[k]);
      for (const auto& [dx, dy] : {std::pair{1, 0}, std::pair{-1, 0}, std::pair{0, 1}, std::pair{0, -1}}) {
        if (x + dx < 0 || y + dy < 0 || x + dx >= reference.width || y + dy >= reference.height) continue;
        if (std::abs(pb::Luminance(reference.At(x + dx, y + dy)) - r) > 0.5 * r) return false;
      }
      return true;
    };
    for (int i = 2; i < argc; ++i) {
      const pb::Image image = pb::ReadExr(argv[i]);
      if (image.width != reference.width || image.height != reference.height)
        throw pb::InputError(argv[i], 0, "size differs from the reference");
      double squares = 0, mean = 0, absolute = 0, worst = 0, smoothSquares = 0, smoothCount = 0;
      for (size_t k = 0; k < image.pixels.size(); ++k) {
        const double y = pb::Luminance(image.pixels[k]), r = pb::Luminance(reference.pixels[k]);
        squares += (y - r) * (y - r);
        absolute += std::abs(y - r);
        worst = std::max(worst, std::abs(y - r));
        mean += y;
        if (smooth(k)) smoothSquares += (y - r) * (y - r), ++smoothCount;
      }
      const double n = double(image.pixels.size());
      fmt::print("{} {:.6g} {:.6g} {:.6g} {:.6g} {:.6g}\n", argv[i], std::sqrt(squares / n) / referenceMean,
                 (mean / n) / referenceMean - 1, absolute / n / referenceMean, worst / referenceMean,
                 std::sqrt(smoothSquares / std::max(smoothCount, 1.0)) / referenceMean);
    }
    return 0;
  } catch (const pb::InputError& e) {
    fmt::print(stderr, "{}\n", e.what());
    return 1;
  }
}
