#include "baker/files/image_io.h"

#include <IexBaseExc.h>
#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfIO.h>
#include <ImfInputFile.h>
#include <ImfOutputFile.h>
#include <ImfStringAttribute.h>
#include <png.h>

#include <ostream>

#include "baker/files/atomic_file.h"
#include "baker/tone_map.h"
#include "mesh/errors.h"

namespace pb {
namespace {

// OpenEXR's output stream over the std::ostream that OutputFiles::Write provides.
class ExrStream : public Imf::OStream {
 public:
  ExrStream(std::ostream& out, const std::string& name) : Imf::OStream(name.c_str()), out_(out) {}
  void write(const char c[], int n) override {
    out_.write(c, n);
    if (!out_) throw InputError(fileName(), 0, "write failed");
  }
  // Never throws: OpenEXR's destructor asks outside its own try block. A failed stream answers -1, which OpenEXR
  // turns into an errno exception (WriteExr names the file).
  uint64_t tellp() override { return uint64_t(out_.tellp()); }
  void seekp(uint64_t pos) override { out_.seekp(std::streamoff(pos)); }

 private:
  std::ostream& out_;
};

Imf::Slice FloatSlice(const Image& image, size_t channel) {
  char* base = const_cast<char*>(reinterpret_cast<const char*>(image.pixels.data())) + channel * sizeof(float);
  return Imf::Slice(Imf::FLOAT, base, sizeof(Rgb), sizeof(Rgb) * size_t(image.width));
}

// One float per pixel, row-major, `width` to a row; `fill` where a file read has no such channel.
Imf::Slice PlaneSlice(const std::vector<float>& plane, int width, double fill = 0.0) {
  char* base = const_cast<char*>(reinterpret_cast<const char*>(plane.data()));
  return Imf::Slice(Imf::FLOAT, base, sizeof(float), sizeof(float) * size_t(width), 1, 1, fill);
}

void PngWrite(png_structp png, png_bytep data, png_size_t length) {
  static_cast<std::ostream*>(png_get_io_ptr(png))->write(reinterpret_cast<const char*>(data), std::streamsize(length));
}
void PngFlush(png_structp) {}

}  // namespace

void WriteExr(OutputFiles& outputs, const std::string& path, const Image& image,
              const std::vector<std::pair<std::string, std::string>>& attributes, const std::vector<float>* alpha,
              const std::vector<ExrChannel>& channels) {
  outputs.Write(path, [&](std::ostream& out) {
    Imf::Header header(image.width, image.height);
    for (const char* c : {"R", "G", "B"}) header.channels().insert(c, Imf::Channel(Imf::FLOAT));
    if (alpha) header.channels().insert("A", Imf::Channel(Imf::FLOAT));
    for (const ExrChannel& c : channels) header.channels().insert(c.name, Imf::Channel(Imf::FLOAT));
    header.insert("quantity", Imf::StringAttribute("radiance"));
    header.insert("units", Imf::StringAttribute("W/(m^2 sr), linear Rec.709 RGB"));
    for (const auto& [key, value] : attributes) header.insert(key, Imf::StringAttribute(value));
    Imf::FrameBuffer frame;
    frame.insert("R", FloatSlice(image, 0));
    frame.insert("G", FloatSlice(image, 1));
    frame.insert("B", FloatSlice(image, 2));
    if (alpha) frame.insert("A", PlaneSlice(*alpha, image.width));
    for (const ExrChannel& c : channels) frame.insert(c.name, PlaneSlice(c.values, image.width));
    ExrStream stream(out, path);
    try {
      Imf::OutputFile file(stream, header);
      file.setFrameBuffer(frame);
      file.writePixels(image.height);
    } catch (const Iex::BaseExc& e) {  // OpenEXR's own (a full disk once aborted the bake from a worker thread)
      throw InputError(path, 0, std::string("cannot write the image: ") + e.what());
    }
  });
}

Image ReadExr(const std::string& path, std::vector<std::pair<std::string, std::string>>* attributes,
              std::vector<float>* alpha, std::vector<ExrChannel>* channels) {
  try {
    Imf::InputFile file(path.c_str());
    if (attributes)
      for (auto it = file.header().begin(); it != file.header().end(); ++it)
        if (const auto* text = dynamic_cast<const Imf::StringAttribute*>(&it.attribute()))
          attributes->emplace_back(it.name(), text->value());
    const Imath::Box2i window = file.header().dataWindow();
    Image image(window.max.x - window.min.x + 1, window.max.y - window.min.y + 1);
    Imf::FrameBuffer frame;
    for (size_t c = 0; c < 3; ++c) frame.insert(c == 0 ? "R" : c == 1 ? "G" : "B", FloatSlice(image, c));
    if (alpha) {
      alpha->assign(image.pixels.size(), 0.0f);
      frame.insert("A", PlaneSlice(*alpha, image.width, 1.0));
    }
    if (channels)
      for (ExrChannel& c : *channels) c.values.assign(image.pixels.size(), 0.0f), frame.insert(c.name, PlaneSlice(c.values, image.width));
    file.setFrameBuffer(frame);
    file.readPixels(window.min.y, window.max.y);
    return image;
  } catch (const std::exception& e) {
    throw InputError(path, 0, std::string("cannot read EXR: ") + e.what());
  }
}

void WritePng(OutputFiles& outputs, const std::string& path, const Image& image, float exposure) {
  std::vector<uint8_t> rgb(size_t(image.width) * size_t(image.height) * 3);
  for (size_t i = 0; i < image.pixels.size(); ++i) {
    const std::array<uint8_t, 3> c = ToneMap(image.pixels[i], exposure);
    std::copy(c.begin(), c.end(), rgb.begin() + std::ptrdiff_t(3 * i));
  }
  WritePngRgb8(outputs, path, image.width, image.height, rgb);
}

void WritePngRgb8(OutputFiles& outputs, const std::string& path, int width, int height, const std::vector<uint8_t>& rgb) {
  PB_CHECK_EQ(rgb.size(), size_t(width) * size_t(height) * 3);
  outputs.Write(path, [&](std::ostream& out) {
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
    png_infop info = png_create_info_struct(png);
    if (!png || !info || setjmp(png_jmpbuf(png))) {
      png_destroy_write_struct(&png, &info);
      throw InputError(path, 0, "PNG encoding failed");
    }
    png_set_write_fn(png, &out, PngWrite, PngFlush);
    png_set_IHDR(png, info, png_uint_32(width), png_uint_32(height), 8, PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE,
                 PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    png_write_info(png, info);
    for (int y = 0; y < height; ++y) png_write_row(png, rgb.data() + size_t(y) * size_t(width) * 3);
    png_write_end(png, nullptr);
    png_destroy_write_struct(&png, &info);
  });
}

}  // namespace pb
