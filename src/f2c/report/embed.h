#pragma once
// What a report page inlines so that it stays one file that works offline: pictures as
// base64, Debian's three.js for the 3D view, and the depth that the top-down slice draws.

#include <string>

#include "f2c/io/sequence.h"
#include "f2c/report/report.h"

namespace f2c {

// A picture as an <img> with its PNG/JPEG bytes inline (base64).
std::string InlineImage(const std::string& encoded_bytes, const std::string& mime, const std::string& alt, int width);

// Debian's three.js and its orbit controls, to inline; empty when libjs-three is absent.
std::string ThreeJs();

// What `frames` evenly spread frames of `seq` saw, for the report's top-down slice (the
// paper's Fig. 1): depth on an 8-pixel grid with normals, a few ms per frame. Needs the
// sequence's intrinsics; frames whose depth cannot be read are left out (the run itself reads
// every frame and says which is bad).
void AddSliceFrames(const RgbdSequence& seq, int frames, ReportInput* in);

}  // namespace f2c
