// levelfuse: depth images, intrinsics and poses.

#include <levelfuse/io/AtomicWrite.h>
#include <levelfuse/io/InputError.h>
#include <levelfuse/io/InputFile.h>
#include <levelfuse/io/MemoryBudget.h>
#include <levelfuse/io/images/DepthImages.h>

#include "../ByteOrder.h"
#include "ExrHeader.h"
#include "../Orthonormal.h"
#include "../FileExtension.h"
#include "ImageSize.h"
#include "PngRead.h"


#if defined(LEVELFUSE_HAVE_OPENEXR)
#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>
#include <ImathBox.h>
#endif

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <utility>

namespace levelfuse::io {

namespace {

namespace fs = std::filesystem;
const float kNoReading = std::numeric_limits<float>::quiet_NaN();

using Problem = detail::ImageProblem;

void requireSize(const std::string& path, double width, double height, const MemoryBudget& budget) {
  Problem problem = "";
  detail::checkImageSize(width, height, detail::kDepthImage, budget, problem);
  if (problem[0] != 0) throw InputError(path, problem);
}

/// Reads a 16-bit grayscale PNG of `fileBytes` bytes into `samples` (host byte
/// order). Returns an error message, empty on success.
std::string readPng16(const char* path, double fileBytes, const MemoryBudget& budget, int& width, int& height,
                      std::vector<std::uint16_t>& samples) {
  std::vector<std::uint8_t> pixels;
  const std::string problem =
      detail::readPngPixels(path, fileBytes, detail::PngPixels::kGray16, detail::kDepthImage, budget, width, height,
                            pixels);
  if (!problem.empty()) return problem;
  samples.resize(pixels.size() / 2);
  std::memcpy(samples.data(), pixels.data(), pixels.size());
  return "";
}

/// Depth images hold metres: a scanner or depth camera measures within metres,
/// lidar within hundreds; an image whose every reading lies beyond this is in
/// other units (a wrong depth scale), and its windows would reach absurdly far.
constexpr double kFarthestNearestReading = 1000.0;

/// Throws InputError if `image` holds readings and all of them lie beyond
/// kFarthestNearestReading.
void requireMetres(const std::string& path, const DepthImage& image) {
  float nearest = std::numeric_limits<float>::infinity();
  for (const float d : image.depth)
    if (std::fabs(d) < nearest) nearest = std::fabs(d);  // NaN, no reading, is never nearer
  if (!(nearest > kFarthestNearestReading) || std::isinf(nearest)) return;
  char text[200];
  std::snprintf(text, sizeof(text),
                "every reading lies beyond 1 km (the nearest at %.3g m): depth images hold metres; check the depth "
                "scale (metres per unit of a 16-bit PNG)", nearest);
  throw InputError(path, text);
}

/// Before OpenEXR is given the file (it allocates what the header declares):
/// the header read with bounded reads, its image's size checked as every
/// reader's is, and its pixels held against what the file can hold.
void requireExrFits(const std::string& path, const MemoryBudget& budget) {
  std::error_code ec;
  const std::uintmax_t fileBytes = fs::file_size(path, ec);
  if (ec) throw InputError(path, "cannot be read (" + ec.message() + ")");
  detail::ExrLayout layout;
  const std::string problem = detail::readExrLayout(path, fileBytes, layout);
  if (!problem.empty()) throw InputError(path, problem);
  requireSize(path, layout.width, layout.height, budget);
  const double pixelBytes = layout.width * layout.height * layout.bytesPerPixel;
  if (pixelBytes > detail::exrMaxCompressionRatio(layout.compression) * static_cast<double>(fileBytes)) {
    Problem text = "";
    std::snprintf(text, sizeof(text),
                  "the header declares %.12g x %.12g pixels (%s of samples), more than the file's %.0f bytes can "
                  "hold (truncated?)", layout.width, layout.height, describeBytes(pixelBytes).c_str(),
                  static_cast<double>(fileBytes));
    throw InputError(path, text);
  }
}

std::vector<double> readNumbers(const std::string& path, std::size_t expected) {
  requireInputFile(path);
  std::ifstream in(path);
  if (!in) throw InputError(path, "cannot be opened for reading");
  std::vector<double> values;
  std::string word;
  while (in >> word) {
    double v = 0.0;
    std::size_t used = 0;
    try {
      v = std::stod(word, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used != word.size()) throw InputError(path, quote(word) + " is not a number");
    if (!std::isfinite(v)) throw InputError(path, "a value is not finite");
    values.push_back(v);
    if (values.size() > expected) break;
  }
  if (values.size() != expected)
    throw InputError(path, "expected " + std::to_string(expected) + " numbers, found " +
                               (values.size() > expected ? "more" : std::to_string(values.size())));
  return values;
}

}  // namespace

DepthImage depthImageFromIntegers(int width, int height, const std::uint16_t* samples, double scale,
                                  const std::vector<unsigned>& invalid) {
  if (!(scale > 0.0) || !std::isfinite(scale)) throw std::invalid_argument("the depth scale must be positive");
  DepthImage image;
  image.width = width;
  image.height = height;
  const std::size_t count = static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
  image.depth.resize(count);
  for (std::size_t i = 0; i < count; ++i) {
    const bool none = std::find(invalid.begin(), invalid.end(), samples[i]) != invalid.end();
    image.depth[i] = none ? kNoReading : static_cast<float>(samples[i] * scale);
  }
  image.step = scale;
  return image;
}

DepthSamples readDepthPngSamples(const std::string& path, const MemoryBudget& budget) {
  requireInputFile(path);
  DepthSamples image;
  std::error_code ec;
  const std::uintmax_t fileBytes = fs::file_size(path, ec);
  if (ec) throw InputError(path, "cannot be read (" + ec.message() + ")");
  const std::string problem =
      readPng16(path.c_str(), static_cast<double>(fileBytes), budget, image.width, image.height, image.samples);
  if (!problem.empty()) throw InputError(path, problem);
  return image;
}

DepthImage readDepthPng(const std::string& path, double scale, const std::vector<unsigned> invalid,
                        const MemoryBudget& budget) {
  if (!(scale > 0.0) || !std::isfinite(scale)) throw InputError(path, "the depth scale must be positive");
  const DepthSamples samples = readDepthPngSamples(path, budget);
  DepthImage image = depthImageFromIntegers(samples.width, samples.height, samples.samples.data(), scale, invalid);
  requireMetres(path, image);
  return image;
}

DepthImage readDepthPfm(const std::string& path, bool positiveOnly, const MemoryBudget& budget) {
  requireInputFile(path);
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, "cannot be opened for reading");
  std::string magic;
  double width = 0, height = 0, scale = 0;
  if (!(in >> magic)) throw InputError(path, "empty file");
  if (magic == "PF") throw InputError(path, "a colour PFM (PF): a depth image has one channel (Pf)");
  if (magic != "Pf") throw InputError(path, "not a PFM file (expected the magic 'Pf')");
  if (!(in >> width >> height >> scale) || width != std::floor(width) || height != std::floor(height) || scale == 0.0)
    throw InputError(path, "a malformed PFM header (expected width, height and a non-zero scale)");
  requireSize(path, width, height, budget);
  // The single whitespace after the scale; a header written on Windows ends its lines in CRLF.
  if (in.get() == '\r' && in.peek() == '\n') in.get();
  DepthImage image;
  image.width = static_cast<int>(width);
  image.height = static_cast<int>(height);
  const std::size_t count = static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
  const auto start = in.tellg();
  in.seekg(0, std::ios::end);
  const auto available = static_cast<std::size_t>(in.tellg() - start);
  if (available < count * sizeof(float))
    throw InputError(path, "the file holds " + std::to_string(available) + " bytes of pixels, " +
                               std::to_string(count * sizeof(float)) + " are declared (truncated?)");
  in.seekg(start);
  std::vector<float> raw(count);
  in.read(reinterpret_cast<char*>(raw.data()), static_cast<std::streamsize>(count * sizeof(float)));
  const bool littleEndian = scale < 0.0;  // a negative scale says little-endian
  for (float& f : raw) detail::toHostOrder(reinterpret_cast<unsigned char*>(&f), sizeof f, littleEndian);
  // PFM rows run bottom to top.
  image.depth.resize(count);
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x) {
      const float d = raw[static_cast<std::size_t>(image.height - 1 - y) * image.width + x];
      image.depth[static_cast<std::size_t>(y) * image.width + x] =
          std::isfinite(d) && (d > 0.0f || !positiveOnly) ? d : kNoReading;
    }
  requireMetres(path, image);
  return image;
}

void writeDepthPfm(const std::string& path, const DepthImage& image) {
  OutputSet outputs;
  writeDepthPfm(outputs, path, image);
  outputs.commit();
}

void writeDepthPfm(OutputSet& outputs, const std::string& path, const DepthImage& image) {
  if (image.width < 1 || image.height < 1 ||
      image.depth.size() != static_cast<std::size_t>(image.width) * static_cast<std::size_t>(image.height))
    throw std::invalid_argument("writeDepthPfm: the image's size and its pixels disagree");
  outputs.add(path, [&](const std::string& temporary) {
    std::ofstream out(temporary, std::ios::binary);
    if (!out) throw std::runtime_error("cannot open a temporary file beside it");
    out << "Pf\n" << image.width << " " << image.height << "\n-1\n";  // negative scale: little-endian
    for (int y = image.height - 1; y >= 0; --y)  // PFM rows run bottom to top
      for (int x = 0; x < image.width; ++x) {
        float d = image.depth[static_cast<std::size_t>(y) * image.width + x];
        unsigned char* b = reinterpret_cast<unsigned char*>(&d);
        detail::toFileOrder(b, sizeof d, true);
        out.write(reinterpret_cast<const char*>(b), 4);
      }
    closeChecked(out);
  });
}

DepthImage readDepthExr(const std::string& path, const MemoryBudget& budget) {
  requireInputFile(path);
  requireExrFits(path, budget);
#if defined(LEVELFUSE_HAVE_OPENEXR)
  try {
    Imf::InputFile file(path.c_str());
    const Imath::Box2i window = file.header().dataWindow();
    const double width = window.max.x - window.min.x + 1.0, height = window.max.y - window.min.y + 1.0;
    requireSize(path, width, height, budget);
    const char* channel = nullptr;
    for (const char* name : {"Z", "Y", "R", "depth", "distance"})
      if (file.header().channels().findChannel(name)) {
        channel = name;
        break;
      }
    if (!channel) throw InputError(path, "no Z, Y, R or depth channel");
    DepthImage image;
    image.width = static_cast<int>(width);
    image.height = static_cast<int>(height);
    std::vector<float> raw(static_cast<std::size_t>(width) * static_cast<std::size_t>(height));
    Imf::FrameBuffer frame;
    char* base = reinterpret_cast<char*>(raw.data()) -
                 (static_cast<std::ptrdiff_t>(window.min.x) + static_cast<std::ptrdiff_t>(window.min.y) * image.width) *
                     static_cast<std::ptrdiff_t>(sizeof(float));
    frame.insert(channel, Imf::Slice(Imf::FLOAT, base, sizeof(float), sizeof(float) * image.width));
    file.setFrameBuffer(frame);
    file.readPixels(window.min.y, window.max.y);
    image.depth.resize(raw.size());
    for (std::size_t i = 0; i < raw.size(); ++i)
      image.depth[i] = std::isfinite(raw[i]) && raw[i] > 0.0f ? raw[i] : kNoReading;
    requireMetres(path, image);
    return image;
  } catch (const InputError&) {
    throw;
  } catch (const std::exception& e) {
    throw InputError(path, "not a readable EXR file (" + excerpt(e.what()) + ")");
  }
#else
  throw InputError(path, "this levelfuse was built without OpenEXR; install libopenexr-dev and rebuild");
#endif
}

DepthImage readDepthImage(const std::string& path, double pngScale, const MemoryBudget& budget) {
  const std::string ext = detail::lowercaseExtension(path);
  if (ext == ".png") return readDepthPng(path, pngScale, {0u, 65535u}, budget);
  if (ext == ".pfm") return readDepthPfm(path, true, budget);
  if (ext == ".exr") return readDepthExr(path, budget);
  throw InputError(path, "unknown depth image type " + quote(ext) + " (expected .png, .pfm or .exr)");
}

void dropReadingsBeyond(DepthImage& image, double maxDepth) {
  for (float& d : image.depth)
    if (d > maxDepth) d = kNoReading;
}

PinholeProjection readIntrinsics(const std::string& path) {
  const std::vector<double> k = readNumbers(path, 9);
  if (k[1] != 0.0 || k[3] != 0.0 || k[6] != 0.0 || k[7] != 0.0 || k[8] != 1.0)
    throw InputError(path, "not a pinhole intrinsics matrix (expected fx 0 cx / 0 fy cy / 0 0 1)");
  if (!(k[0] > 0.0) || !(k[4] > 0.0)) throw InputError(path, "the focal lengths must be positive");
  return PinholeProjection{k[0], k[4], k[2], k[5]};
}

openvdb::math::Mat4d poseFromRowMajor(const std::vector<double>& m, const std::string& file,
                                      const std::string& where) {
  if (m.size() != 16) throw InputError(file, where + "a pose needs 16 numbers");
  for (double v : m)
    if (!std::isfinite(v)) throw InputError(file, where + "the pose holds a non-finite number");
  if (std::fabs(m[12]) + std::fabs(m[13]) + std::fabs(m[14]) > 1e-9 || std::fabs(m[15] - 1.0) > 1e-9)
    throw InputError(file, where + "the pose's last row must be 0 0 0 1");
  // Column-vector convention in, OpenVDB's row vectors out: the transpose.
  openvdb::math::Mat4d pose(m[0], m[4], m[8], m[12], m[1], m[5], m[9], m[13], m[2], m[6], m[10], m[14], m[3], m[7],
                            m[11], m[15]);
  const openvdb::math::Mat3d r = pose.getMat3();
  if (orthonormalityError(r) > 1e-2)
    throw InputError(file, where + "the pose's rotation is not orthonormal: not a rigid motion");
  if (r.det() < 0.0) throw InputError(file, where + "the pose mirrors space (determinant -1)");
  // Tracked camera poses are orthonormal to a few parts in a thousand: take the nearest rotation.
  pose.setMat3(nearestRotation(r));
  return pose;
}

openvdb::math::Mat4d readPose(const std::string& path) { return poseFromRowMajor(readNumbers(path, 16), path, ""); }

RangeMap depthFrame(DepthImage image, const PinholeProjection& intrinsics, const openvdb::math::Mat4d& cameraToWorld,
                    const DepthNoise& noise, const std::string& name) {
  RangeMap map =
      RangeMap::pinhole(image.width, image.height, std::move(image.depth), intrinsics, cameraToWorld, noise, name);
  map.setReadingStep(image.step);
  return map;
}

}  // namespace levelfuse::io
