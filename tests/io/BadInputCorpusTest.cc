// The bad-input corpus (tests/data/bad): every file makes its reader throw an
// InputError that names the file and says what is wrong with it, without
// crashing, hanging or allocating more than a small file can justify.

#include "LargestAllocation.h"
#include "support/InputErrors.h"

#include <levelfuse/io/Ply.h>
#include <levelfuse/io/images/ColourImages.h>
#include <levelfuse/io/images/DepthImages.h>
#include <levelfuse/io/scans/E57Scans.h>
#include <levelfuse/io/scans/Manifest.h>
#include <levelfuse/io/scans/PointScans.h>
#include <levelfuse/io/scans/PtxScans.h>
#include <levelfuse/io/scans/Scans.h>
#include <levelfuse/io/scans/StanfordScans.h>
#include <levelfuse/io/vdb/VdbFile.h>
#include <levelfuse/recon/Reconstructor.h>

#include <gtest/gtest.h>

#include <cctype>
#include <filesystem>
#include <iterator>
#include <set>
#include <string>
#include <vector>

namespace levelfuse::io {
namespace {

namespace fs = std::filesystem;

enum class Reader { kPly, kRangeGrid, kStanfordConf, kManifest, kDepthPng, kDepthPfm, kDepthExr, kIntrinsics, kPose,
                    kFolder, kPtx, kE57, kPoints, kKittiBin, kKittiCalib, kVdb, kReconstruction, kColourPng };

struct BadInput {
  const char* file;      ///< below tests/data/bad; a folder of depth frames for kFolder
  Reader reader;
  const char* fragment;  ///< what the message must say
  const char* culprit = nullptr;  ///< the file the message names, if another one (a scan the file refers to)
};

void PrintTo(const BadInput& input, std::ostream* out) { *out << input.file; }

// clang-format off
const BadInput kCorpus[] = {
  // PLY, ASCII and binary (readPly)
  {"ply/empty.ply", Reader::kPly, "the header has no end_header line (empty or truncated file?)"},
  {"ply/not-ply.ply", Reader::kPly, "not a PLY file (the first line is not 'ply')"},
  {"ply/binary-garbage.ply", Reader::kPly, "not a PLY file"},
  {"ply/truncated-header.ply", Reader::kPly, "the header has no end_header line"},
  {"ply/no-format.ply", Reader::kPly, "the header has no format line"},
  {"ply/unknown-format.ply", Reader::kPly, "header line 2: unknown format 'binary_middle_endian'"},
  {"ply/unknown-type.ply", Reader::kPly, "header line 4: unknown type 'float128'"},
  {"ply/float-list-count.ply", Reader::kPly, "header line 4: invalid list count type 'float'"},
  {"ply/negative-element-count.ply", Reader::kPly, "header line 3: element 'vertex' has an invalid count '-3'"},
  {"ply/property-before-element.ply", Reader::kPly, "header line 3: a property before any element"},
  {"ply/huge-count-ascii.ply", Reader::kPly, "element 'vertex' declares 99999999999 entries, but only 6 bytes follow the header"},
  {"ply/huge-count-binary.ply", Reader::kPly, "element 'vertex' declares 4000000000 entries, but only 12 bytes follow the header"},
  {"ply/huge-count-no-properties.ply", Reader::kPly, "element 'vertex' declares 18446744073709551615 entries but no properties"},
  {"ply/huge-count-no-properties-ascii.ply", Reader::kPly, "element 'vertex' declares 18446744073709551615 entries but no properties"},
  {"ply/truncated-ascii.ply", Reader::kPly, "the file ends in 'vertex' entry 2 of 3 (truncated?)"},
  {"ply/truncated-binary.ply", Reader::kPly, "element 'vertex' declares 3 entries, but only 28 bytes follow the header"},
  {"ply/truncated-binary-list.ply", Reader::kPly, "the file ends in 'face' entry 1 (truncated?)"},
  {"ply/too-few-values.ply", Reader::kPly, "line 9: 'vertex' entry 1 has fewer values than its 3 properties"},
  {"ply/too-many-values.ply", Reader::kPly, "line 9: 'vertex' entry 1 has more values than its 3 properties"},
  {"ply/not-a-number.ply", Reader::kPly, "line 9: 'one' is not a number"},
  {"ply/integer-out-of-range.ply", Reader::kPly, "line 8: 300.000000 does not fit the integer type of 'vertex'"},
  {"ply/fractional-list-length.ply", Reader::kPly, "line 6: 2.500000 does not fit the integer type of 'face'"},
  {"ply/data-after-last-element.ply", Reader::kPly, "line 11: data after the last declared element"},
  {"ply/negative-list-length.ply", Reader::kPly, "'face' entry 0 has a negative list length"},
  // Range-grid scans (readRangeGridPly, then rangeMapFromScan)
  {"scan/nan-coordinate.ply", Reader::kRangeGrid, "vertex 4 has a coordinate that is not finite"},
  {"scan/inf-coordinate-binary.ply", Reader::kRangeGrid, "vertex 2 has a coordinate that is not finite"},
  {"scan/index-out-of-range.ply", Reader::kRangeGrid, "range_grid entry 8 (row 2, column 2) points at vertex 17, but there are 9"},
  {"scan/negative-index.ply", Reader::kRangeGrid, "range_grid entry 2 (row 0, column 2) points at vertex -1, but there are 9"},
  {"scan/two-vertices-in-a-cell.ply", Reader::kRangeGrid, "range_grid entry 4 (row 1, column 1) lists 2 vertices; at most 1 is allowed"},
  {"scan/grid-count-mismatch.ply", Reader::kRangeGrid, "range_grid has 8 entries, but num_rows x num_cols = 3 x 3 = 9"},
  {"scan/missing-num-rows.ply", Reader::kRangeGrid, "the header's 'obj_info num_rows' is missing or not a positive size"},
  {"scan/huge-grid-dimensions.ply", Reader::kRangeGrid, "the header's 'obj_info num_rows' is missing or not a positive size"},
  {"scan/no-range-grid.ply", Reader::kRangeGrid, "no 'range_grid' element: not a range scan"},
  {"scan/list-coordinates.ply", Reader::kRangeGrid, "the vertices have no scalar x, y and z"},
  {"scan/no-neighbouring-samples.ply", Reader::kRangeGrid, "the range grid has no neighbouring samples: nothing to triangulate"},
  {"scan/huge-extent.ply", Reader::kRangeGrid, "the scan would need a range map of 2e+33 x 11 pixels of 0.0005 m, more than the 4096 its 3 x 3 grid allows: choose a larger pixel size"},
  {"scan/infinite-extent.ply", Reader::kRangeGrid, "the scan would need a range map of inf x 11 pixels"},
  {"scan/sparse-map-from-nine-points.ply", Reader::kRangeGrid, "the scan would need a range map of 8731131 x 8 pixels"},
  // Stanford .conf files (loadStanfordScans)
  {"conf/empty.conf", Reader::kStanfordConf, "no 'bmesh' lines: the file places no scans"},
  {"conf/only-a-camera.conf", Reader::kStanfordConf, "no 'bmesh' lines: the file places no scans"},
  {"conf/binary-garbage.conf", Reader::kStanfordConf, "line 1: unknown entry"},
  {"conf/quaternion-not-unit.conf", Reader::kStanfordConf, "line 1: the quaternion has norm 2.000000, not 1: not a rotation"},
  {"conf/quaternion-zero.conf", Reader::kStanfordConf, "line 2: the quaternion is zero: it describes no rotation"},
  {"conf/too-few-numbers.conf", Reader::kStanfordConf, "line 1: expected 'bmesh FILE tx ty tz qi qj qk qr'"},
  {"conf/not-a-number.conf", Reader::kStanfordConf, "line 1: 'zero' is not a number"},
  {"conf/nan-translation.conf", Reader::kStanfordConf, "line 1: 'nan' is not a finite number"},
  {"conf/trailing-words.conf", Reader::kStanfordConf, "line 1: unexpected 'extra' after the quaternion"},
  {"conf/unknown-entry.conf", Reader::kStanfordConf, "line 2: unknown entry 'scan' (expected bmesh, mesh or camera)"},
  {"conf/missing-scan-file.conf", Reader::kStanfordConf, "line 1: scan file 'nowhere.ply' does not exist"},
  // Found by FuzzStanfordConf: std::filesystem threw on a name longer than the system allows.
  {"conf/file-name-too-long.conf", Reader::kStanfordConf, "line 1: scan file 'aaaaaaaa"},
  // JSON manifests (loadManifest); support/ holds the valid files they refer to
  {"manifest/empty.json", Reader::kManifest, "not valid JSON"},
  {"manifest/truncated.json", Reader::kManifest, "not valid JSON"},
  {"manifest/binary-garbage.json", Reader::kManifest, "not valid JSON"},
  {"manifest/deeply-nested.json", Reader::kManifest, "scans[0]: expected an object"},
  {"manifest/scans-not-an-array.json", Reader::kManifest, "expected an object with an array 'scans'"},
  {"manifest/scans-empty.json", Reader::kManifest, "'scans' is empty"},
  {"manifest/entry-not-an-object.json", Reader::kManifest, "scans[0]: expected an object"},
  {"manifest/missing-format.json", Reader::kManifest, "scans[0]: missing 'format'"},
  {"manifest/format-not-a-string.json", Reader::kManifest, "scans[0]: 'format' must be a string"},
  {"manifest/unknown-format.json", Reader::kManifest, "scans[0]: unknown format 'lidar'"},
  {"manifest/missing-scan-file.json", Reader::kManifest, "scans[0]: 'file': no such file"},
  {"manifest/pose-too-short.json", Reader::kManifest, "scans[0]: 'pose' needs 16 numbers"},
  {"manifest/pose-with-a-string.json", Reader::kManifest, "scans[0]: 'pose' holds something that is not a number"},
  {"manifest/depth-scale-not-a-number.json", Reader::kManifest, "scans[0]: 'depth_scale' must be a number"},
  {"manifest/depth-scale-overflows.json", Reader::kManifest, "not valid JSON ([json.exception.out_of_range.406] number overflow"},
  {"manifest/sigma-minimum-not-a-number.json", Reader::kManifest, "scans[0]: 'sigma.minimum' must be a number"},
  {"manifest/sigma-wrong-type.json", Reader::kManifest, "scans[0]: 'sigma' must be a number or"},
  {"manifest/intrinsics-not-an-object.json", Reader::kManifest, "scans[0]: 'intrinsics' needs a number 'fx'"},
  {"manifest/quaternion-not-unit.json", Reader::kManifest, "scans[0]: 'quaternion' has norm 3.000000: a rotation needs a unit quaternion"},
  {"manifest/translation-too-short.json", Reader::kManifest, "scans[0]: 'translation' needs 3 numbers"},
  {"manifest/depth-scale-beyond-a-kilometre.json", Reader::kManifest, "every reading lies beyond 1 km (the nearest at 1.8e+32 m): depth images hold metres; check the depth scale", "support/depth.png"},
  {"manifest/focal-length-of-a-thousandth.json", Reader::kManifest, "scans[0]: range map 'depth.png': focal lengths of 0.001 x 0.001 pixels give a 4 x 4 image a field of view of 179.9"},
  {"manifest/focal-length-of-1e-300.json", Reader::kManifest, "scans[0]: range map 'depth.png': focal lengths of 1e-300 x 1e-300 pixels give a 4 x 4 image a field of view of 180 degrees, more than the 170 of a pinhole camera"},
  {"manifest/one-pixel-image.json", Reader::kManifest, "the image has 1 x 1 pixels; a depth image needs at least 2 x 2", "png/one-pixel.png"},
  {"manifest/spherical-rows-past-the-pole.json", Reader::kManifest, "scans[0]: range map 'plane.pfm': its rows reach a pole (elevations from 80.000000 to 95.000000 degrees)"},
  {"manifest/spherical-without-an-azimuth-step.json", Reader::kManifest, "scans[0]: missing 'azimuth_step' (degrees)"},
  {"manifest/spherical-more-than-a-turn.json", Reader::kManifest, "scans[0]: range map 'plane.pfm': its 4 columns span more than a turn"},
  {"manifest/spherical-step-of-zero.json", Reader::kManifest, "scans[0]: range map 'plane.pfm': the angular steps must be finite and not zero"},
  {"manifest/spherical-row-elevations-and-step.json", Reader::kManifest, "scans[0]: give 'row_elevations' or 'elevation_start' and 'elevation_step', not both"},
  {"manifest/spherical-row-elevations-not-one-per-row.json", Reader::kManifest, "scans[0]: 'row_elevations' needs 4 numbers"},
  {"manifest/spherical-row-elevations-decreasing.json", Reader::kManifest, "scans[0]: range map 'plane.pfm': the row elevations must be finite and strictly increasing (row 1)"},
  // Depth PNG (readDepthPng)
  {"png/empty.png", Reader::kDepthPng, "not a PNG file"},
  {"png/not-a-png.png", Reader::kDepthPng, "not a PNG file"},
  {"png/8-bit.png", Reader::kDepthPng, "has 8-bit samples; a depth image needs 16 bits"},
  {"png/rgb.png", Reader::kDepthPng, "not a grayscale image (PNG colour type 2)"},
  {"png/gray-alpha.png", Reader::kDepthPng, "not a grayscale image (PNG colour type 4)"},
  {"png/palette.png", Reader::kDepthPng, "not a grayscale image (PNG colour type 3)"},
  {"png/truncated.png", Reader::kDepthPng, "truncated PNG data (the file ends inside a chunk)"},
  {"png/bad-crc.png", Reader::kDepthPng, "corrupt PNG data (IHDR: CRC error)"},
  {"png/zero-width.png", Reader::kDepthPng, "corrupt PNG data (Invalid IHDR data)"},
  {"png/one-pixel.png", Reader::kDepthPng, "the image has 1 x 1 pixels; a depth image needs at least 2 x 2"},
  {"png/huge-dimensions.png", Reader::kDepthPng, "the header declares 100000 x 100000 pixels: too large for a depth image"},
  {"png/chunk-longer-than-the-file.png", Reader::kDepthPng, "truncated PNG data (the file ends inside a chunk)"},
  {"png/text-chunk-of-512-mib.png", Reader::kDepthPng, "truncated PNG data (the file ends inside a chunk)"},
  {"png/not-a-png.png", Reader::kColourPng, "not a PNG file"},
  {"png/truncated.png", Reader::kColourPng, "truncated PNG data (the file ends inside a chunk)"},
  {"png/bad-crc.png", Reader::kColourPng, "corrupt PNG data (IHDR: CRC error)"},
  {"png/zero-width.png", Reader::kColourPng, "corrupt PNG data (Invalid IHDR data)"},
  {"png/huge-dimensions.png", Reader::kColourPng, "the header declares 100000 x 100000 pixels: too large for a colour image"},
  {"png/text-chunk-of-512-mib.png", Reader::kColourPng, "truncated PNG data (the file ends inside a chunk)"},
  {"png/declares-more-than-it-holds.png", Reader::kColourPng, "the header declares 16000 x 16000 pixels, more than the file's 74 bytes can hold"},
  {"manifest/colour-not-a-png.json", Reader::kManifest, "not a PNG file", "png/not-a-png.png"},
  {"manifest/colour-truncated.json", Reader::kManifest, "truncated PNG data", "png/truncated.png"},
  {"manifest/colour-of-another-size.json", Reader::kManifest, "pixels for a range map of", "png/palette.png"},
  {"manifest/colour-not-a-string.json", Reader::kManifest, "scans[0]: 'colour'"},
  {"png/declares-more-than-it-holds.png", Reader::kDepthPng, "the header declares 16000 x 16000 pixels, more than the file's 74 bytes can hold"},
  // PFM (readDepthPfm)
  {"pfm/empty.pfm", Reader::kDepthPfm, "empty file"},
  {"pfm/bad-magic.pfm", Reader::kDepthPfm, "not a PFM file (expected the magic 'Pf')"},
  {"pfm/colour.pfm", Reader::kDepthPfm, "a colour PFM (PF): a depth image has one channel (Pf)"},
  {"pfm/malformed-header.pfm", Reader::kDepthPfm, "a malformed PFM header"},
  {"pfm/zero-scale.pfm", Reader::kDepthPfm, "a malformed PFM header"},
  {"pfm/negative-width.pfm", Reader::kDepthPfm, "the image has -2 x 2 pixels; a depth image needs at least 2 x 2"},
  {"pfm/one-pixel.pfm", Reader::kDepthPfm, "the image has 1 x 1 pixels; a depth image needs at least 2 x 2"},
  {"pfm/truncated.pfm", Reader::kDepthPfm, "the file holds 19 bytes of pixels, 24 are declared (truncated?)"},
  {"pfm/huge-dimensions.pfm", Reader::kDepthPfm, "the header declares 100000 x 100000 pixels: too large for a depth image"},
  {"pfm/every-reading-beyond-a-kilometre.pfm", Reader::kDepthPfm, "every reading lies beyond 1 km (the nearest at 1.2e+29 m)"},
  {"pfm/absurd-dimensions.pfm", Reader::kDepthPfm, "the header declares 1e+300 x 1e+300 pixels: too large for a depth image"},
  // EXR (readDepthExr; also without OpenEXR, which the message then says)
  {"exr/not-an-exr.exr", Reader::kDepthExr, "EXR"},
  {"exr/truncated.exr", Reader::kDepthExr, "EXR"},
  // Checked before OpenEXR allocates what the header declares.
  {"exr/declares-more-than-it-holds.exr", Reader::kDepthExr, "the header declares 16384 x 4096 pixels (256 MiB of samples), more than the file's 2325 bytes can hold (truncated?)"},
  {"exr/attribute-longer-than-the-file.exr", Reader::kDepthExr, "the EXR header's attribute 'channels' declares 1073741824 bytes, more than the file holds (truncated?)"},
  // Camera files (readIntrinsics, readPose)
  {"camera/intrinsics-skewed.txt", Reader::kIntrinsics, "not a pinhole intrinsics matrix (expected fx 0 cx / 0 fy cy / 0 0 1)"},
  {"camera/intrinsics-nan.txt", Reader::kIntrinsics, "a value is not finite"},
  {"camera/intrinsics-word.txt", Reader::kIntrinsics, "'fy' is not a number"},
  {"camera/intrinsics-negative-focal-length.txt", Reader::kIntrinsics, "the focal lengths must be positive"},
  {"camera/pose-too-few-numbers.txt", Reader::kPose, "expected 16 numbers, found 12"},
  {"camera/pose-too-many-numbers.txt", Reader::kPose, "expected 16 numbers, found more"},
  {"camera/pose-mirrored.txt", Reader::kPose, "the pose mirrors space (determinant -1)"},
  {"camera/pose-scaled.txt", Reader::kPose, "the pose's rotation is not orthonormal: not a rigid motion"},
  {"camera/pose-projective.txt", Reader::kPose, "the pose's last row must be 0 0 0 1"},
  {"camera/pose-binary-garbage.txt", Reader::kPose, "is not a number"},
  // Folders of depth frames (loadScans): the frame or file at fault is named
  {"7scenes/frame-without-pose", Reader::kFolder, "no pose beside it (expected ", "7scenes/frame-without-pose/frame-000000.depth.png"},
  {"7scenes/sheared-pose", Reader::kFolder, "the pose's rotation is not orthonormal: not a rigid motion", "7scenes/sheared-pose/frame-000000.pose.txt"},
  {"7scenes/8-bit-frame", Reader::kFolder, "has 8-bit samples; a depth image needs 16 bits", "7scenes/8-bit-frame/frame-000000.depth.png"},
  {"7scenes/truncated-frame", Reader::kFolder, "truncated PNG data (the file ends inside a chunk)", "7scenes/truncated-frame/frame-000000.depth.png"},
  {"tum/frame-without-pose", Reader::kFolder, "no pose in groundtruth.txt within 0.02 s of the frame's time 10.500000 (the nearest, line 4, is 0.49 s away)", "tum/frame-without-pose/depth/10.500000.png"},
  {"tum/non-unit-quaternion", Reader::kFolder, "line 3: the quaternion has norm 2.000000, not 1: not a rotation", "tum/non-unit-quaternion/groundtruth.txt"},
  {"tum/8-bit-frame", Reader::kFolder, "has 8-bit samples; a depth image needs 16 bits", "tum/8-bit-frame/depth/10.000000.png"},
  {"tum/truncated-frame", Reader::kFolder, "truncated PNG data (the file ends inside a chunk)", "tum/truncated-frame/depth/10.000000.png"},
  {"tum/missing-image", Reader::kFolder, "line 2: depth image 'depth/10.000000.png' does not exist (looked for ", "tum/missing-image/depth.txt"},
  {"tum/no-groundtruth", Reader::kFolder, "a TUM RGB-D folder (it holds depth.txt) without groundtruth.txt"},
  {"tum/timestamp-not-a-number", Reader::kFolder, "line 2: 'ten' is not a number", "tum/timestamp-not-a-number/depth.txt"},
  {"tum/pose-too-few-numbers", Reader::kFolder, "line 1: expected 'timestamp tx ty tz qx qy qz qw'", "tum/pose-too-few-numbers/groundtruth.txt"},
  {"tum/no-frames", Reader::kFolder, "no frames: expected lines 'timestamp filename'", "tum/no-frames/depth.txt"},
  // PTX files (loadPtxScans): a scan of 2 columns x 3 rows, lines 1 to 10 its header, 11 to 16 its points
  {"ptx/truncated.ptx", Reader::kPtx, "the file ends after line 14, before point 5 of the 6 (2 columns x 3 rows) of scan 1 (truncated?)"},
  {"ptx/rows-and-columns-disagree-with-the-points.ptx", Reader::kPtx, "line 15: a point line after the 4 points scan 1 (lines 1 to 14) declares (2 columns x 2 rows): its columns and rows disagree with its points"},
  {"ptx/non-rigid-transform.ptx", Reader::kPtx, "line 9: the transform's rows 1 to 3 (lines 7 to 9) are not orthonormal (their dot products are off by up to 3, more than 0.0001): not a rigid motion"},
  {"ptx/skewed-scanner-axes.ptx", Reader::kPtx, "line 6: the scanner's axes (lines 4 to 6) are not orthonormal (their dot products are off by up to 0.5, more than 0.0001)"},
  {"ptx/nan.ptx", Reader::kPtx, "line 13: 'nan' is not a finite number"},
  {"ptx/huge-declared-size.ptx", Reader::kPtx, "line 2: scan 1 declares 2147483647 columns x 2147483647 rows, 4611686014132420609 points, but the "},
  {"ptx/mixed-field-counts.ptx", Reader::kPtx, "line 13: expected point 3 of the 6 (2 columns x 3 rows) of scan 1 with 4 fields as the scan's first point (line 11), found 7 fields"},
  {"ptx/colour-above-255.ptx", Reader::kPtx, "line 14: '300' is not a colour (a whole number from 0 to 255)"},
  {"ptx/no-returns.ptx", Reader::kPtx, "scan 1 (lines 1 to 16) has no returns: all its 6 points are 0 0 0"},
  // Its returns' azimuths lie 1e-7 rad apart but span a radian: a grid of 30 million pixels for 10 points.
  {"ptx/points-off-their-grid.ptx", Reader::kPtx, "scan 1 (lines 1 to 20): its returns span up to 3e+07 pixels of its grid's steps (1e-07 x 0.1 rad), more than 4 per point of its 5 columns x 2 rows: its points do not lie on one scanner's grid"},
  // Its 16 points look along 4 directions only: 4 columns and 4 rows that repeat each other's angles.
  {"ptx/points-sharing-pixels.ptx", Reader::kPtx, "scan 1 (lines 1 to 26): its 16 returns fill only 4 pixels of its grid (2 x 2 of 0.1 x 0.1 rad): its points do not lie on one scanner's grid"},
  {"ptx/garbage-after-the-last-scan.ptx", Reader::kPtx, "line 18: 'end of scans' after scan 1 (lines 1 to 16): neither the column count of another scan"},
  // E57 files (loadE57Scans): a station of 8 x 6 rays written whole, then damaged or made to lie
  {"e57/truncated.e57", Reader::kE57, "a size of 1500 bytes is not a whole number of E57's 1024-byte pages: truncated?"},
  {"e57/page-checksum-fails.e57", Reader::kE57, "page 0 (bytes 0 to 1023) fails its CRC-32C checksum: the file is damaged"},
  {"e57/xml-cut-short.e57", Reader::kE57, "its XML section does not parse: Error parsing start element tag at byte 792 of 793"},
  {"e57/offset-beyond-the-file.e57", Reader::kE57, "the section of the points of scan 1 ('hall') is placed at byte 4000000000, beyond the file's 3072 bytes"},
  {"e57/huge-record-count.e57", Reader::kE57, "the points of scan 1 ('hall') declare 1099511627776 records, whose field 'cartesianX' alone needs more than the 714 bytes of their section"},
  {"e57/two-to-the-forty-constant-records.e57", Reader::kE57, "reading the 1099511627776 records of scan 1 ('hall') needs about 48 TiB of memory"},
  {"e57/bit-width-over-64.e57", Reader::kE57, "scan 1 ('hall'): the field 'intensity''s maximum is '36893488147419103232', beyond a 64-bit integer"},
  {"e57/unknown-codec.e57", Reader::kE57, "scan 1 ('hall'): its points name a codec ('zlibCodec'); levelfuse reads E57's default, bit packing, alone"},
  {"e57/unknown-packet-type.e57", Reader::kE57, "the points of scan 1 ('hall'): the packet at logical byte 80 is of type 7 (expected 0, 1 or 2: index, data or empty)"},
  {"e57/no-returns.e57", Reader::kE57, "scan 1 ('hall') has no returns: none of its 48 records holds a valid position"},
  // Point files (readPointCloud, by extension) and KITTI sweeps and calibrations
  {"points/nan.xyz", Reader::kPoints, "line 2: 'nan' is not a finite number"},
  {"points/mixed-field-counts.xyz", Reader::kPoints, "line 2: expected 4 fields as the first point (line 1), found 3"},
  {"points/colour-300.xyz", Reader::kPoints, "line 2: '300' is not a colour (a whole number from 0 to 255)"},
  {"points/empty.xyz", Reader::kPoints, "no points: the file is empty, blank or only comments"},
  {"points/ply-without-x.ply", Reader::kPoints, "the vertices have no x, y and z"},
  {"points/huge-vertex-count.ply", Reader::kPoints, "element 'vertex' declares 4000000000 entries, but only 12 bytes follow the header"},
  {"kitti/truncated.bin", Reader::kKittiBin, "a size of 20 bytes is not a whole number of points of 16 bytes"},
  {"kitti/nan.bin", Reader::kKittiBin, "point 1 (at byte 16) has a coordinate that is not finite"},
  {"kitti/empty.bin", Reader::kKittiBin, "no points: the file is empty"},
  {"kitti/tr-scaled.txt", Reader::kKittiCalib, "line 2: 'Tr:' (velodyne to camera 0): the pose's rotation is not orthonormal: not a rigid motion"},
  {"manifest/points-origin-and-pose.json", Reader::kManifest, "scans[0]: give one of the sensor's 'origin', 'pose' and 'pose_file', not 2"},
  {"manifest/points-non-rigid-pose.json", Reader::kManifest, "scans[0]: the pose's rotation is not orthonormal: not a rigid motion"},
  {"manifest/kitti-frame-beyond-the-poses.json", Reader::kManifest, "frame 2 is beyond the file's 2 poses (frames 0 to 1)", "support/poses.txt"},
  {"manifest/kitti-non-rigid-tr.json", Reader::kManifest, "line 2: 'Tr:' (velodyne to camera 0): the pose's rotation is not orthonormal", "kitti/tr-scaled.txt"},
  // .vdb files (readVdb): truncated and corrupted copies of a small float level set
  {"vdb/empty.vdb", Reader::kVdb, "not a valid .vdb file: the header: the file ends in the magic number (8 bytes needed, 0 left; truncated?)"},
  {"vdb/not-a-vdb.vdb", Reader::kVdb, "the file does not start with OpenVDB's magic number"},
  {"vdb/truncated-header.vdb", Reader::kVdb, "the file ends in the UUID (36 bytes needed, 9 left; truncated?)"},
  {"vdb/truncated-half.vdb", Reader::kVdb, "grid 'ls' (1 of 1): the grid ends at byte 10139, beyond the file's 5069 bytes (truncated?)"},
  {"vdb/truncated-last-byte.vdb", Reader::kVdb, "the grid ends at byte 10139, beyond the file's 10138 bytes (truncated?)"},
  {"vdb/future-version.vdb", Reader::kVdb, "file format version 300; levelfuse reads versions 222 to 224"},
  {"vdb/huge-grid-count.vdb", Reader::kVdb, "the file declares 2147483647 grids; the 10074 bytes left cannot hold them"},
  {"vdb/huge-metadata-count.vdb", Reader::kVdb, "the grid's metadata declares 4294967295 items, more than the 10012 bytes left can hold"},
  {"vdb/huge-name-length.vdb", Reader::kVdb, "a grid's name declares 4294967295 bytes; levelfuse reads at most 65536"},
  {"vdb/huge-delayed-load-count.vdb", Reader::kVdb, "delayed-load metadata declares 2147483647 leaf nodes, more than the file holds"},
  {"vdb/offsets-beyond-the-end.vdb", Reader::kVdb, "the grid ends at byte 1099511627776, beyond the file's 10139 bytes"},
  // OpenVDB read the 8-byte count of a leaf's raw values into a buffer of 24 bytes.
  {"vdb/raw-block-of-a-terabyte.vdb", Reader::kVdb, "a node's values are stored as 1099511627776 raw bytes; they take 24"},
  {"vdb/blosc-header-disagrees.vdb", Reader::kVdb, "the blosc header declares 1073741824 bytes compressed into 16; expected 0 in 16"},
  {"vdb/unaligned-root-child.vdb", Reader::kVdb, "a root child (100, 0, 0) is not a multiple of 4096"},
  {"vdb/slot-both-child-and-value.vdb", Reader::kVdb, "a node's slot is both a child and a value"},
  {"vdb/unknown-value-kind.vdb", Reader::kVdb, "a node's values are of unknown kind 9 (expected 0 to 6)"},
  {"vdb/unknown-transform.vdb", Reader::kVdb, "a transform of type 'FrustumScaleMap'; levelfuse reads the linear maps"},
  {"vdb/infinite-transform.vdb", Reader::kVdb, "the transform holds a number that is not finite"},
  {"vdb/zero-voxel-size.vdb", Reader::kVdb, "grid 'ls' has voxels of size [0, 0, 0]: not a usable transform"},
  // Found by FuzzVdb: half floats whose grid metadata lacks 'is_saved_as_half_float', which OpenVDB
  // reads as full floats; a block then failed to decompress inside the topology and OpenVDB leaked its node.
  {"vdb/half-floats-without-their-flag.vdb", Reader::kVdb, "a node's values: 0 bytes compressed (blosc) into 1, which blosc never does"},
  {"vdb/bool-grid.vdb", Reader::kVdb, "grid 'b' is of type 'Tree_bool_5_4_3'; levelfuse reads grids of float, double, int32, int64, vec3s, vec3d and vec3i values"},
  // Scans that read well but that no reconstruction can take: parameters checked against the data
  {"reconstruct/sigma-of-1e300.json", Reader::kReconstruction, "a window width epsilon of 1e+300 (the scans' median sigma) is wider than the data, which span 0.06: a reading would speak for the whole scene; choose a window width epsilon of at most 0.06"},
  {"reconstruct/spacing-of-1e-40.conf", Reader::kReconstruction, "a voxel size of 1e-40 (the scans' median distance between rays) is below the smallest a grid can have, 1.5e-05"},
};
// clang-format on

/// Valid files that the corpus's manifests refer to.
const char* const kSupportFiles[] = {"support/depth.png", "support/intrinsics.txt", "support/plane.pfm",
                                     "support/spacing-of-1e-40.ply", "support/points.xyz", "support/velodyne.bin",
                                     "support/calib.txt", "support/poses.txt"};

/// No corpus file may make a reader allocate more than this at once.
constexpr std::size_t kMaxAllocation = 16 << 20;
constexpr std::uintmax_t kMaxCorpusFileBytes = 64 << 10;

std::string corpusPath(const std::string& relative) {
  return (fs::path(LEVELFUSE_TEST_DATA_DIR) / "bad" / relative).string();
}

/// The corpus files an entry stands for: the file, or every file below the folder.
std::vector<std::string> filesOf(const std::string& path) {
  if (!fs::is_directory(path)) return {path};
  std::vector<std::string> files;
  for (const auto& entry : fs::recursive_directory_iterator(path))
    if (entry.is_regular_file()) files.push_back(entry.path().string());
  return files;
}

void read(Reader reader, const std::string& path) {
  switch (reader) {
    case Reader::kPly: readPly(path); break;
    case Reader::kRangeGrid:
      rangeMapFromScan(readRangeGridPly(path), openvdb::math::Mat4d::identity(), StanfordScanOptions(), path);
      break;
    case Reader::kStanfordConf: loadStanfordScans(path); break;
    case Reader::kManifest: loadManifest(path); break;
    case Reader::kDepthPng: readDepthPng(path); break;
    case Reader::kColourPng: readColourPng(path); break;
    case Reader::kDepthPfm: readDepthPfm(path); break;
    case Reader::kDepthExr: readDepthExr(path); break;
    case Reader::kIntrinsics: readIntrinsics(path); break;
    case Reader::kPose: readPose(path); break;
    case Reader::kFolder: loadScans(path); break;
    case Reader::kPtx: loadPtxScans(path); break;
    case Reader::kE57: loadE57Scans(path); break;
    case Reader::kPoints: readPointCloud(path); break;
    case Reader::kKittiBin: readKittiBin(path); break;
    case Reader::kKittiCalib: readKittiVelodyneToCamera(path); break;
    case Reader::kVdb: readVdb(path); break;
    case Reader::kReconstruction:
      // The reconstruction's refusal, of the inputs, in the library's words (the CLI adds its flags).
      try {
        Reconstructor(loadScans(path)).linearSolution();
      } catch (const std::invalid_argument& e) {
        throw InputError(path, e.what());
      } catch (const InsufficientMemory& e) {
        throw InputError(path, e.what());
      }
      break;
  }
}

class BadInputCorpus : public ::testing::TestWithParam<BadInput> {};

TEST_P(BadInputCorpus, ThrowsAnInputErrorNamingTheFileAndTheProblem) {
  const BadInput& input = GetParam();
  const std::string path = corpusPath(input.file);
  for (const std::string& file : filesOf(path)) {
    std::error_code ec;
    ASSERT_LE(fs::file_size(file, ec), kMaxCorpusFileBytes) << file << (ec ? ": missing" : ": not a small file");
  }
  test::LargestAllocation largest;
  const std::string culprit = input.culprit ? corpusPath(input.culprit) : path;
  test::expectInputError([&] { read(input.reader, path); }, culprit, input.fragment);
  EXPECT_LE(largest.bytes(), kMaxAllocation) << "reading " << path << " allocated " << largest.bytes() << " bytes at once";
}

std::string testName(const ::testing::TestParamInfo<BadInput>& info) {
  // A file read by two readers (a PNG as depth and as colour) is named for both.
  std::string name = std::string(info.param.reader == Reader::kColourPng ? "colour_" : "") + info.param.file;
  for (char& c : name)
    if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
  return name;
}

INSTANTIATE_TEST_SUITE_P(Files, BadInputCorpus, ::testing::ValuesIn(kCorpus), testName);

TEST(BadInputCorpusProbe, SeesTheLargestAllocation) {
  test::LargestAllocation largest;
  std::vector<char> block(3 << 20);
  EXPECT_GE(largest.bytes(), block.size());
}

TEST(BadInputCorpusListing, EveryFileInTheFolderIsListed) {
  std::set<std::string> listed(std::begin(kSupportFiles), std::end(kSupportFiles));
  for (const BadInput& input : kCorpus) {
    // A PNG is listed once as a depth image, and may be once more as a colour image.
    const bool asColour = input.reader == Reader::kColourPng;
    EXPECT_TRUE(asColour || listed.insert(input.file).second) << input.file << " is listed twice";
    if (input.reader != Reader::kFolder) continue;
    listed.erase(input.file);  // a folder stands for its files
    for (const std::string& file : filesOf(corpusPath(input.file)))
      listed.insert(fs::relative(file, corpusPath("")).generic_string());
  }
  std::set<std::string> present;
  for (const auto& entry : fs::recursive_directory_iterator(corpusPath("")))
    if (entry.is_regular_file()) present.insert(fs::relative(entry.path(), corpusPath("")).generic_string());
  for (const std::string& file : present) EXPECT_TRUE(listed.count(file)) << file << " is in the corpus but not listed";
  for (const std::string& file : listed) EXPECT_TRUE(present.count(file)) << file << " is listed but missing";
  EXPECT_GE(present.size(), 30u);
}

}  // namespace
}  // namespace levelfuse::io
