// A small C interface to FastNoise2 for benchmarks/noise.py (loaded with ctypes).
// Our own code (sylva's licence); it only calls FastNoise2's public C++ API (MIT).
// Build: see the docstring of benchmarks/noise.py.
#include <FastNoise/FastNoise.h>

namespace {
struct Node {
    FastNoise::SmartNode<> node;
};
}  // namespace

extern "C" {

// kind: 0 Perlin, 1 Simplex (OpenSimplex2-style), 2 Value, 3 Cellular F1 (Euclidean);
// octaves > 1 wraps it in FractalFBm (gain 0.5, lacunarity 2); avx2 != 0 caps the SIMD
// level at AVX2.  Returns an opaque handle (null when the level is not available).
void* sfn2_new(int kind, int octaves, int avx2) {
    FastSIMD::FeatureSet fs = avx2 ? FastSIMD::FeatureSet::AVX2 : FastSIMD::FeatureSet::Max;
    FastNoise::SmartNode<> src;
    // feature scale 1: one lattice cell per unit, as sylva's and FastNoise Lite's grids
    if (kind == 0) {
        auto n = FastNoise::New<FastNoise::Perlin>(fs);
        if (!n) return nullptr;
        n->SetScale(1.0f);
        src = n;
    } else if (kind == 1) {
        auto n = FastNoise::New<FastNoise::Simplex>(fs);
        if (!n) return nullptr;
        n->SetScale(1.0f);
        src = n;
    } else if (kind == 2) {
        auto n = FastNoise::New<FastNoise::Value>(fs);
        if (!n) return nullptr;
        n->SetScale(1.0f);
        src = n;
    } else {
        auto c = FastNoise::New<FastNoise::CellularDistance>(fs);
        if (!c) return nullptr;
        c->SetScale(1.0f);
        c->SetDistanceFunction(FastNoise::DistanceFunction::Euclidean);
        c->SetReturnType(FastNoise::CellularDistance::ReturnType::Index0);
        src = c;
    }
    if (!src) return nullptr;
    if (octaves > 1) {
        auto f = FastNoise::New<FastNoise::FractalFBm>(fs);
        f->SetSource(src);
        f->SetOctaveCount(octaves);
        f->SetGain(0.5f);
        f->SetLacunarity(2.0f);
        src = f;
    }
    return new Node{src};
}

void sfn2_free(void* h) { delete static_cast<Node*>(h); }

const char* sfn2_level(void* h) {
    return FastSIMD::GetFeatureSetString(static_cast<Node*>(h)->node->GetActiveFeatureSet());
}

void sfn2_grid2(void* h, float* out, int nx, int ny, float step, int seed) {
    static_cast<Node*>(h)->node->GenUniformGrid2D(out, 0.0f, 0.0f, nx, ny, step, step, seed);
}

void sfn2_grid3(void* h, float* out, int nx, int ny, int nz, float step, int seed) {
    static_cast<Node*>(h)->node->GenUniformGrid3D(
        out, 0.0f, 0.0f, 0.0f, nx, ny, nz, step, step, step, seed);
}

// The 4D grid of kind 1 (Simplex) or 2 (Value), as sfn2_grid3.
void sfn2_grid4(void* h, float* out, int nx, int ny, int nz, int nw, float step, int seed) {
    static_cast<Node*>(h)->node->GenUniformGrid4D(
        out, 0.0f, 0.0f, 0.0f, 0.0f, nx, ny, nz, nw, step, step, step, step, seed);
}

// Domain warping, FastNoise2's nearest to sylva's: the noise of sfn2_new(kind, octaves)
// sampled at positions moved by FastNoise2's gradient warp (DomainWarpGradient, amplitude
// `amp` cells), in `octaves` independent fBm octaves (DomainWarpFractalIndependent).
void* sfn2_new_warp(int kind, int octaves, int avx2, float amp) {
    Node* base = static_cast<Node*>(sfn2_new(kind, octaves, avx2));
    if (!base) return nullptr;
    FastSIMD::FeatureSet fs = avx2 ? FastSIMD::FeatureSet::AVX2 : FastSIMD::FeatureSet::Max;
    auto w = FastNoise::New<FastNoise::DomainWarpGradient>(fs);
    w->SetSource(base->node);
    w->SetWarpAmplitude(amp);
    w->SetScale(1.0f);
    FastNoise::SmartNode<> out = w;
    if (octaves > 1) {
        auto f = FastNoise::New<FastNoise::DomainWarpFractalIndependent>(fs);
        f->SetSource(w);
        f->SetOctaveCount(octaves);
        f->SetGain(0.5f);
        f->SetLacunarity(2.0f);
        out = f;
    }
    delete base;
    return new Node{out};
}

}  // extern "C"
