// bsdf_values.cpp: prints pbrt-v3's own BSDF::f and BSDF::Pdf for a few materials at fixed
// directions, as the C table that examples/render/tests/test_render_pbrtv3_bsdf.c pins our
// materials.c / reflection.c against. It links pbrt-v3's objects (built by bench/pbrt_v3/compare.sh)
// and runs each material's own ComputeScatteringFunctions (CreateXMaterial from the same parameter
// list our parser reads), so the numbers come from pbrt-v3's code, not ours.
//
// Regenerate:  sh bench/pbrt_v3/compare.sh bsdf   (prints the table; paste it into the test)
//
// The frame is pbrt-v3's BSDF frame of a SurfaceInteraction with dpdu = x, dpdv = y: n = ns = ng = z,
// ss = x, ts = y (our elr_onb gives the same frame for n = z). Directions are printed as the floats
// used, so the test evaluates ours at exactly the same vectors.
#include "pbrt.h"
#include "paramset.h"
#include "interaction.h"
#include "reflection.h"
#include "memory.h"
#include "texture.h"
#include "materials/plastic.h"
#include "materials/metal.h"
#include "materials/substrate.h"
#include "materials/uber.h"
#include "materials/glass.h"
#include "materials/matte.h"
#include <cstdio>
#include <cmath>
#include <map>
#include <vector>

using namespace pbrt;

// the materials, in pbrt-v3 scene syntax (the test hands the same text to our parser)
static const char *kMaterials[] = {
    "Material \"plastic\" \"rgb Kd\" [ .4 .2 .2 ] \"rgb Ks\" [ .5 .5 .5 ] \"float roughness\" [ .025 ]",
    "Material \"plastic\" \"rgb Kd\" [ .4 .5 .4 ] \"rgb Ks\" [ .3 .3 .3 ] \"float roughness\" [ .15 ]",
    "Material \"plastic\" \"rgb Kd\" [ .2 .3 .4 ] \"rgb Ks\" [ .6 .5 .4 ] \"float roughness\" [ .2 ] \"bool remaproughness\" \"false\"",
    "Material \"metal\"",
    "Material \"metal\" \"float uroughness\" [ .3 ] \"float vroughness\" [ .1 ] \"bool remaproughness\" \"false\"",
    "Material \"metal\" \"float roughness\" [ .2 ] \"rgb eta\" [ 1.5 1 .5 ] \"rgb k\" [ 3 4 5 ]",
    "Material \"substrate\" \"rgb Kd\" [ .6 .3 .2 ] \"rgb Ks\" [ .2 .4 .1 ] \"float uroughness\" [ .2 ] \"float vroughness\" [ .05 ]",
    "Material \"uber\" \"rgb Kd\" [ .5 .4 .3 ] \"rgb Ks\" [ .3 .3 .3 ] \"float roughness\" [ .05 ]",
    "Material \"uber\" \"rgb Kd\" [ .5 .4 .3 ] \"rgb Ks\" [ .3 .3 .3 ] \"float uroughness\" [ .3 ] \"float vroughness\" [ .1 ] \"float index\" [ 1.8 ]",
    "Material \"glass\" \"float uroughness\" [ .15 ] \"float vroughness\" [ .3 ]",
    "Material \"glass\" \"float roughness\" [ .1 ] \"float index\" [ 1.33 ] \"bool remaproughness\" \"false\"",
    "Material \"matte\" \"rgb Kd\" [ .5 .25 .125 ]",
    "Material \"matte\" \"rgb Kd\" [ .5 .25 .125 ] \"float sigma\" [ 20 ]",
    "Material \"matte\" \"rgb Kd\" [ .7 .6 .5 ] \"float sigma\" [ 90 ]",
    "Material \"matte\" \"rgb Kd\" [ .5 -.25 .125 ]",
    "Material \"plastic\" \"rgb Kd\" [ -.2 .3 .4 ] \"rgb Ks\" [ .5 -.1 .2 ] \"float roughness\" [ .1 ]",
};

// a minimal reader of the parameter list above: "type name" value | [ values ]
static ParamSet ParseParams(const std::string &s, std::string *type) {
    ParamSet ps;
    std::vector<std::string> tok;
    for (size_t i = 0; i < s.size();) {
        if (isspace((unsigned char)s[i])) { ++i; continue; }
        if (s[i] == '"') { size_t j = s.find('"', i + 1); tok.push_back(s.substr(i, j - i + 1)); i = j + 1; continue; }
        if (s[i] == '[' || s[i] == ']') { tok.push_back(std::string(1, s[i])); ++i; continue; }
        size_t j = i; while (j < s.size() && !isspace((unsigned char)s[j]) && s[j] != ']') ++j;
        tok.push_back(s.substr(i, j - i)); i = j;
    }
    *type = tok[1].substr(1, tok[1].size() - 2);
    for (size_t i = 2; i < tok.size();) {
        std::string decl = tok[i].substr(1, tok[i].size() - 2), ty = decl.substr(0, decl.find(' ')), name = decl.substr(decl.find(' ') + 1);
        std::vector<std::string> vals;
        ++i;
        if (tok[i] == "[") { ++i; while (tok[i] != "]") vals.push_back(tok[i++]); ++i; }
        else vals.push_back(tok[i++]);
        int n = (int)vals.size();
        if (ty == "bool") { std::unique_ptr<bool[]> b(new bool[n]); for (int k = 0; k < n; ++k) b[k] = vals[k] == "\"true\""; ps.AddBool(name, std::move(b), n); }
        else {
            std::unique_ptr<Float[]> f(new Float[n]);
            for (int k = 0; k < n; ++k) f[k] = (Float)atof(vals[k].c_str());
            if (ty == "rgb") ps.AddRGBSpectrum(name, std::move(f), n); else ps.AddFloat(name, std::move(f), n);
        }
    }
    return ps;
}

static Vector3f Sph(double thetaDeg, double phiDeg) {
    double t = thetaDeg * Pi / 180, p = phiDeg * Pi / 180;
    return Normalize(Vector3f((Float)(std::sin(t) * std::cos(p)), (Float)(std::sin(t) * std::sin(p)), (Float)std::cos(t)));
}

int main() {
    // (theta_o, phi_o, theta_i, phi_i) in degrees; theta > 90 is below the surface. Chosen to cover
    // the specular peak, plastic's total-internal-reflection region of FresnelDielectric(1.5, 1)
    // (incidence on the microfacet past 41.8 degrees), both directions below the shading normal (a
    // mesh whose normals point inwards, as pbrt-v3's loopsubdiv makes them), transmission and grazing.
    static const double dirs[][4] = {
        {0, 0, 30, 10},     {60, 0, 60, 180},   {60, 0, 55, 170},  {75, 0, 75, 180},   {80, 30, 70, 200},
        {45, 90, 20, 250},  {30, 45, 35, 215},  {88, 0, 85, 175},  {120, 0, 120, 180}, {105, 0, 105, 180},
        {135, 90, 160, 250}, {100, 30, 110, 200}, {30, 0, 140, 180}, {130, 60, 50, 250}, {20, 0, 170, 10},
        {70, 135, 65, 315},
    };
    const int nd = sizeof(dirs) / sizeof(dirs[0]), nm = sizeof(kMaterials) / sizeof(kMaterials[0]);
    std::map<std::string, std::shared_ptr<Texture<Float>>> ft;
    std::map<std::string, std::shared_ptr<Texture<Spectrum>>> st;
    MemoryArena arena;
    printf("/* generated by bench/pbrt_v3/bsdf_values.cpp from pbrt-v3 %s: {material, wo, wi, f rgb, pdf} */\n", PBRT_V3_COMMIT);
    for (int m = 0; m < nm; ++m) {
        std::string type;
        ParamSet geom, mp = ParseParams(kMaterials[m], &type);
        TextureParams tp(geom, mp, ft, st);
        Material *mat = nullptr;
        if (type == "plastic") mat = CreatePlasticMaterial(tp);
        else if (type == "metal") mat = CreateMetalMaterial(tp);
        else if (type == "substrate") mat = CreateSubstrateMaterial(tp);
        else if (type == "uber") mat = CreateUberMaterial(tp);
        else if (type == "glass") mat = CreateGlassMaterial(tp);
        else if (type == "matte") mat = CreateMatteMaterial(tp);
        for (int d = 0; d < nd; ++d) {
            Vector3f wo = Sph(dirs[d][0], dirs[d][1]), wi = Sph(dirs[d][2], dirs[d][3]);
            SurfaceInteraction si(Point3f(0, 0, 0), Vector3f(0, 0, 0), Point2f(.5f, .5f), wo, Vector3f(1, 0, 0),
                                  Vector3f(0, 1, 0), Normal3f(0, 0, 0), Normal3f(0, 0, 0), 0, nullptr);
            mat->ComputeScatteringFunctions(&si, arena, TransportMode::Radiance, true);
            Spectrum f = si.bsdf->f(wo, wi);
            Float pdf = si.bsdf->Pdf(wo, wi), rgb[3];
            f.ToRGB(rgb);
            printf("  {%d, {%.9g, %.9g, %.9g}, {%.9g, %.9g, %.9g}, {%.9g, %.9g, %.9g}, %.9g},\n", m, wo.x, wo.y, wo.z, wi.x, wi.y,
                   wi.z, rgb[0], rgb[1], rgb[2], pdf);
            arena.Reset();
        }
        delete mat;
    }
    return 0;
}
