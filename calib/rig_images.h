// The images of a camera rig: one source per camera, its images paired into synchronised frames.
//
// A source is a folder (its images, as ListImageFiles: png, jpg, jpeg, tif, tiff, bmp, sorted) or
// a glob on the file name ('dir/left*.jpg', quoted so the shell leaves it: * and ? and [..] in
// the last path component only; the matching image files of dir, sorted).
// Each image gets a key from its stem (the file name without extension):
//   1. the source's common prefix and suffix are removed from every stem, never cutting a run of
//      digits in two ("left01".."left14" -> "01".."14"; a source of one image keeps its stem);
//   2. when most images of every source have a digit in what is left, the key is the number of
//      its last run of digits (so left7.png pairs with right07.png, as mrcal pairs by the number
//      in the names) and an image without one is unpaired; otherwise the key is what is left, as
//      text (left_a.png <-> right_a.png).
// Images of different sources with the same key form a frame; a key seen by fewer than
// RigImageOptions::min_cameras_per_frame sources leaves its images unpaired, listed with their
// source (never dropped silently). Errors (Summary::error, naming the source): a source that
// matches no image, two images of one source with the same key, no key shared by any two sources.
#pragma once

#include <string>
#include <vector>

namespace calibench {

struct RigImageOptions {
  // A frame needs images of at least this many cameras (2..number of sources); 2 keeps every
  // pair, the number of sources keeps only frames every camera saw.
  int min_cameras_per_frame = 2;
  bool Check(std::string* why) const;
};

struct RigImageFrame {
  std::string key;                          // The shared key ("7" or the stem's middle).
  std::vector<std::string> path_by_camera;  // One per source; empty: that camera has no image.
};

struct UnpairedImage {
  int source = 0;  // Index into the sources.
  std::string path;
};

struct RigImageSummary {
  bool ok = false;
  std::string error;                    // Why not ok, naming the source.
  bool keyed_by_number = false;         // Rule 2's number, else the text.
  std::vector<int> images_per_source;   // How many images each source matched.
  std::vector<RigImageFrame> frames;    // By key (numbers ascending, else text order).
  std::vector<UnpairedImage> unpaired;  // By source, then file name.
  // A few lines: per source its images, the frames, the unpaired images with their source.
  std::string Report(const std::vector<std::string>& sources) const;
};

// The image files of one source (a folder or a glob, header comment), sorted. False with *why
// naming the source when it cannot be listed or matches no image.
bool ListSourceImages(const std::string& source, std::vector<std::string>* files, std::string* why);

// Pairs the images of `sources` (one per camera, at least 2) into frames (header comment).
RigImageSummary PairRigImages(const std::vector<std::string>& sources,
                              const RigImageOptions& options = {});

}  // namespace calibench
