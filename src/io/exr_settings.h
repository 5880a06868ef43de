// How the project writes and reads its OpenEXR files (maps, HDR images, correspondence maps):
// one place for the compression and the threading, which every writer and reader applies.
#pragma once

#include <ImfCompression.h>

namespace acq {

// PIZ (lossless wavelet + Huffman). Measured on a 2048 x 2048 session's files (1636 x 1636 map of
// 64 float planes; one core, docs/svbrdf-map.md): the map 574 MB written in 7.1 s against ZIP's
// 644 MB in 21.6 s (ZIP hardly compresses float coefficients and was most of the reconstruction's
// time); an HDR image 12 MB in 0.26 s against 16 MB in 0.42 s; a correspondence map 38 MB in
// 0.62 s against 58 MB in 1.9 s. Reading is about as fast as ZIP. Files written with ZIP before
// still read: the reader takes any compression.
constexpr Imf::Compression kExrCompression = Imf::PIZ_COMPRESSION;

// OpenEXR compresses and decompresses a file's chunks on its own thread pool, which is empty
// unless asked for: sized to the machine's cores, once per process (idempotent, thread-safe).
void UseExrThreads();

}  // namespace acq
