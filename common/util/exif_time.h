// When an image was taken, as cameras record it in EXIF: DateTimeOriginal
// (the camera clock's "YYYY:MM:DD hh:mm:ss"), SubSecTimeOriginal (digits
// of that second) and OffsetTimeOriginal (the clock's zone, "+02:00"; EXIF
// 2.31). Read from and written into JPEG (an APP1 segment) and PNG (an eXIf
// chunk, PNG 1.5) bytes through libexif.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace uw {

// The capture time of a JPEG or PNG image as Unix time (s, UTC), or nullopt
// when the image has no EXIF or no DateTimeOriginal. A time without
// OffsetTimeOriginal is on the clock `zone_offset_s` east of UTC; without
// that either it is an error (a camera's clock in local time: hours of
// ambiguity). Throws uw::Error naming `name` on a time that is not one and
// on bytes that are neither JPEG nor PNG. `zone_stated`, when given, is
// set to whether the image stated its zone.
std::optional<double> ReadExifCaptureTime(
    const std::vector<unsigned char>& image, const std::string& name,
    std::optional<int> zone_offset_s = std::nullopt,
    bool* zone_stated = nullptr);
// The same for a file (named in messages by its path).
std::optional<double> ReadExifCaptureTime(
    const std::filesystem::path& path,
    std::optional<int> zone_offset_s = std::nullopt,
    bool* zone_stated = nullptr);

// `image` (JPEG or PNG bytes without EXIF) with an EXIF block stating the
// capture time `unix_s` on a clock `zone_offset_s` east of UTC, to the
// microsecond, as a camera writes it. Throws uw::Error on other bytes and
// on an image that has EXIF already.
std::vector<unsigned char> WithExifCaptureTime(
    const std::vector<unsigned char>& image, double unix_s, int zone_offset_s);

}  // namespace uw
