// The untrusted inputs Penumbra reads, as fuzz targets (libFuzzer's entry point): a glTF (text or
// binary), a scene file, a texture image, an .xyz point file. Each target must return for every
// input -- an Error or a result -- and never crash, hang, read outside its folder or allocate
// without a bound. Built by scripts/fuzz.sh with clang's libFuzzer under ASan + UBSan; in the
// ordinary build each target is linked with replay_main.cpp and run over its seeds and every input
// that once crashed (tests/fuzz/regressions/<target>/).
#pragma once

#include <cstddef>
#include <cstdint>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size);
