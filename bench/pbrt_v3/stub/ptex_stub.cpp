// Ptex is not needed for the comparison scenes: the two factories report an error.
#include "textures/ptex.h"
#include "error.h"
namespace pbrt {
PtexTexture<Float> *CreatePtexFloatTexture(const Transform &, const TextureParams &) { Error("ptex not built"); return nullptr; }
PtexTexture<Spectrum> *CreatePtexSpectrumTexture(const Transform &, const TextureParams &) { Error("ptex not built"); return nullptr; }
}
