#include "common/util/exif_time.h"

#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <memory>

#include <libexif/exif-data.h>
#include <zlib.h>

#include "common/util/error.h"
#include "common/util/file.h"
#include "common/util/time_text.h"

namespace uw {
namespace {

using Bytes = std::vector<unsigned char>;
using ExifDataPtr = std::unique_ptr<ExifData, decltype(&exif_data_unref)>;

constexpr unsigned char kPngSignature[8] = {0x89, 'P',  'N',  'G',
                                            0x0D, 0x0A, 0x1A, 0x0A};
// What starts an EXIF block in a JPEG APP1 segment, and what libexif reads
// and writes; a PNG eXIf chunk holds the block without it.
constexpr unsigned char kExifHeader[6] = {'E', 'x', 'i', 'f', 0, 0};

bool IsPng(const Bytes& image) {
  return image.size() >= 8 &&
         std::memcmp(image.data(), kPngSignature, sizeof(kPngSignature)) == 0;
}

bool IsJpeg(const Bytes& image) {
  return image.size() >= 4 && image[0] == 0xFF && image[1] == 0xD8;
}

uint32_t BigEndian32(const unsigned char* bytes) {
  return uint32_t{bytes[0]} << 24 | uint32_t{bytes[1]} << 16 |
         uint32_t{bytes[2]} << 8 | uint32_t{bytes[3]};
}

void AppendBigEndian32(uint32_t value, Bytes* bytes) {
  for (const int shift : {24, 16, 8, 0}) {
    bytes->push_back(static_cast<unsigned char>(value >> shift));
  }
}

// The PNG chunk at `offset`: its data length, checked to lie in the image.
uint32_t PngChunkLength(const Bytes& image, size_t offset,
                        const std::string& name) {
  const uint32_t length = BigEndian32(&image[offset]);
  if (length > image.size() - offset - 12) {
    throw ErrorAt(name, ": damaged PNG (a chunk runs past the end)");
  }
  return length;
}

// The image's EXIF block, starting with kExifHeader, or empty when it has
// none.
Bytes ExifBlock(const Bytes& image, const std::string& name) {
  if (IsPng(image)) {
    for (size_t offset = 8; offset + 12 <= image.size();) {
      const uint32_t length = PngChunkLength(image, offset, name);
      const auto type = [&](const char* what) {
        return std::memcmp(&image[offset + 4], what, 4) == 0;
      };
      if (type("eXIf")) {
        Bytes block(std::begin(kExifHeader), std::end(kExifHeader));
        block.insert(block.end(), image.begin() + offset + 8,
                     image.begin() + offset + 8 + length);
        return block;
      }
      if (type("IEND")) break;
      offset += 12 + length;
    }
    return {};
  }
  if (IsJpeg(image)) {
    size_t offset = 2;
    while (offset + 4 <= image.size() && image[offset] == 0xFF) {
      const unsigned char marker = image[offset + 1];
      if (marker == 0xFF) {  // a fill byte
        ++offset;
        continue;
      }
      // Start of scan or end of image: the metadata segments are behind.
      if (marker == 0xDA || marker == 0xD9) break;
      const size_t length = size_t{image[offset + 2]} << 8 | image[offset + 3];
      if (length < 2 || offset + 2 + length > image.size()) {
        throw ErrorAt(name, ": damaged JPEG (a segment runs past the end)");
      }
      if (marker == 0xE1 && length >= 2 + sizeof(kExifHeader) &&
          std::memcmp(&image[offset + 4], kExifHeader, sizeof(kExifHeader)) ==
              0) {
        return Bytes(image.begin() + offset + 4,
                     image.begin() + offset + 2 + length);
      }
      offset += 2 + length;
    }
    return {};
  }
  throw ErrorAt(name, ": neither a JPEG nor a PNG image");
}

// An ASCII tag without its terminating zero and padding; empty when absent.
std::string AsciiTag(ExifData* data, ExifTag tag) {
  ExifEntry* entry = exif_data_get_entry(data, tag);
  if (entry == nullptr || entry->format != EXIF_FORMAT_ASCII ||
      entry->data == nullptr) {
    return "";
  }
  const char* text = reinterpret_cast<const char*>(entry->data);
  std::string value(text, strnlen(text, entry->size));
  const size_t last = value.find_last_not_of(' ');
  return last == std::string::npos ? "" : value.substr(0, last + 1);
}

void AddAsciiTag(ExifData* data, ExifTag tag, const std::string& text) {
  ExifMem* memory = exif_mem_new_default();
  ExifEntry* entry = exif_entry_new_mem(memory);
  entry->tag = tag;
  entry->format = EXIF_FORMAT_ASCII;
  entry->components = text.size() + 1;
  entry->size = static_cast<unsigned int>(text.size() + 1);
  entry->data =
      static_cast<unsigned char*>(exif_mem_alloc(memory, entry->size));
  std::memcpy(entry->data, text.c_str(), entry->size);
  exif_content_add_entry(data->ifd[EXIF_IFD_EXIF], entry);
  exif_entry_unref(entry);
  exif_mem_unref(memory);
}

}  // namespace

std::optional<double> ReadExifCaptureTime(const Bytes& image,
                                          const std::string& name,
                                          std::optional<int> zone_offset_s,
                                          bool* zone_stated) {
  const Bytes block = ExifBlock(image, name);
  if (block.empty()) return std::nullopt;
  const ExifDataPtr data(
      exif_data_new_from_data(block.data(),
                              static_cast<unsigned int>(block.size())),
      exif_data_unref);
  if (!data) throw ErrorAt(name, ": cannot read its EXIF");
  const std::string date = AsciiTag(data.get(), EXIF_TAG_DATE_TIME_ORIGINAL);
  // EXIF writes an unknown time as blanks and colons.
  if (date.find_first_not_of(" :") == std::string::npos) return std::nullopt;
  const std::string where = name + ": EXIF DateTimeOriginal '" + date + "'";
  if (date.size() != 19 || date[4] != ':' || date[7] != ':' ||
      date[10] != ' ') {
    throw ErrorAt(where, " is not YYYY:MM:DD hh:mm:ss");
  }
  std::string iso = date.substr(0, 4) + "-" + date.substr(5, 2) + "-" +
                    date.substr(8, 2) + "T" + date.substr(11);
  const std::string fraction =
      AsciiTag(data.get(), EXIF_TAG_SUB_SEC_TIME_ORIGINAL);
  if (!fraction.empty()) iso += "." + fraction;
  // The zone the camera states wins over the one the caller assumes.
  const std::string zone = AsciiTag(data.get(), EXIF_TAG_OFFSET_TIME_ORIGINAL);
  if (zone_stated != nullptr) *zone_stated = !zone.empty();
  iso += zone;
  return ParseIsoTime(iso, where, zone_offset_s);
}

std::optional<double> ReadExifCaptureTime(const std::filesystem::path& path,
                                          std::optional<int> zone_offset_s,
                                          bool* zone_stated) {
  const std::string text = ReadFileToString(path);
  return ReadExifCaptureTime(Bytes(text.begin(), text.end()), path.string(),
                             zone_offset_s, zone_stated);
}

Bytes WithExifCaptureTime(const Bytes& image, double unix_s,
                          int zone_offset_s) {
  if (!ExifBlock(image, "the image").empty()) {
    throw ErrorAt("the image has EXIF already");
  }
  // "2024-10-08T19:53:20.250000+02:00" into EXIF's three fields.
  const std::string iso = IsoTimeText(unix_s, zone_offset_s, 6);
  std::string date = iso.substr(0, 19);
  date[4] = date[7] = ':';
  date[10] = ' ';
  const ExifDataPtr data(exif_data_new(), exif_data_unref);
  exif_data_set_byte_order(data.get(), EXIF_BYTE_ORDER_INTEL);
  AddAsciiTag(data.get(), EXIF_TAG_DATE_TIME_ORIGINAL, date);
  AddAsciiTag(data.get(), EXIF_TAG_SUB_SEC_TIME_ORIGINAL, iso.substr(20, 6));
  AddAsciiTag(data.get(), EXIF_TAG_OFFSET_TIME_ORIGINAL,
              zone_offset_s == 0 ? "+00:00" : ZoneOffsetText(zone_offset_s));
  unsigned char* saved = nullptr;
  unsigned int size = 0;
  exif_data_save_data(data.get(), &saved, &size);
  const std::unique_ptr<unsigned char, decltype(&std::free)> owned(saved,
                                                                   std::free);
  if (saved == nullptr || size <= sizeof(kExifHeader) ||
      std::memcmp(saved, kExifHeader, sizeof(kExifHeader)) != 0) {
    throw ErrorAt("libexif could not write the capture time");
  }
  Bytes result;
  if (IsPng(image)) {
    // After IHDR, which comes first: before the image data, where readers
    // look for it.
    const size_t after_header = 8 + 12 + PngChunkLength(image, 8, "the image");
    result.assign(image.begin(), image.begin() + after_header);
    const size_t chunk = result.size();
    AppendBigEndian32(size - sizeof(kExifHeader), &result);
    result.insert(result.end(), {'e', 'X', 'I', 'f'});
    result.insert(result.end(), saved + sizeof(kExifHeader), saved + size);
    AppendBigEndian32(static_cast<uint32_t>(
                          crc32(0, &result[chunk + 4],
                                static_cast<uInt>(result.size() - chunk - 4))),
                      &result);
    result.insert(result.end(), image.begin() + after_header, image.end());
  } else if (IsJpeg(image)) {
    // After SOI and a JFIF APP0, which must come first.
    size_t after = 2;
    if (image.size() > 6 && image[2] == 0xFF && image[3] == 0xE0) {
      after += 2 + (size_t{image[4]} << 8 | image[5]);
    }
    const size_t length = size + 2;
    if (length > 0xFFFF) throw ErrorAt("the EXIF block is too long for JPEG");
    result.assign(image.begin(), image.begin() + after);
    result.insert(result.end(),
                  {0xFF, 0xE1, static_cast<unsigned char>(length >> 8),
                   static_cast<unsigned char>(length & 0xFF)});
    result.insert(result.end(), saved, saved + size);
    result.insert(result.end(), image.begin() + after, image.end());
  } else {
    throw ErrorAt("the image is neither a JPEG nor a PNG");
  }
  return result;
}

}  // namespace uw
