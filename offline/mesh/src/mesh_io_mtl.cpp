// ngi offline: the MTL reader (see mesh_io_mtl.h; statements after Wavefront's "MTL material
// format", Lightwave-era spec, and the PBR extension's Pm/Pr/Ke).
#include "mesh_io_mtl.h"

#include <algorithm>
#include <cmath>

namespace ngi::mesh_io {
namespace {

std::string_view trim(std::string_view text)
{
    while (!text.empty() && (text.front() == ' ' || text.front() == '\t')) text.remove_prefix(1);
    while (!text.empty() && (text.back() == ' ' || text.back() == '\t' || text.back() == '\r')) text.remove_suffix(1);
    return text;
}

class MtlParser {
public:
    MtlParser(const Input& library, std::vector<std::string>& warnings)
        : library_(library), lines_(library), warnings_(warnings)
    {}

    std::vector<MtlMaterial> parse()
    {
        std::string_view line;
        while (lines_.next(line)) {
            const size_t hash = line.find('#');
            if (hash != std::string_view::npos) line = line.substr(0, hash);
            std::string_view rest = line;
            const std::string_view keyword = nextToken(rest);
            if (keyword.empty()) continue;
            if (keyword == "newmtl") {
                materials_.emplace_back();
                materials_.back().material.name = std::string(trim(rest));
                materials_.back().material.metallicFactor = 0.0;
                continue;
            }
            if (materials_.empty()) continue;  // statements before the first newmtl describe nothing
            MtlMaterial& m = materials_.back();
            if (keyword == "Kd") {
                const glm::dvec3 kd = colour(rest);
                m.material.baseColorFactor = glm::dvec4(kd, m.material.baseColorFactor.a);
            } else if (keyword == "d") {
                m.material.baseColorFactor.a = std::clamp(number(rest, "d"), 0.0, 1.0);
                m.hasDissolve = true;
            } else if (keyword == "Tr") {  // transparency: d wins where both are given
                if (!m.hasDissolve) m.material.baseColorFactor.a = 1.0 - std::clamp(number(rest, "Tr"), 0.0, 1.0);
            } else if (keyword == "Ke") {
                m.material.emissiveFactor = colour(rest);
                m.hasEmissiveFactor = true;
            } else if (keyword == "Pm") {
                m.material.metallicFactor = std::clamp(number(rest, "Pm"), 0.0, 1.0);
            } else if (keyword == "Pr") {
                m.material.roughnessFactor = std::clamp(number(rest, "Pr"), 0.0, 1.0);
            } else if (keyword == "map_Kd") {
                m.baseColor = texture(rest, nullptr);
            } else if (keyword == "map_Bump" || keyword == "map_bump" || keyword == "bump" || keyword == "norm") {
                m.normal = texture(rest, &m.material.normalScale);
            } else if (keyword == "map_Ke") {
                m.emissive = texture(rest, nullptr);
            } else if (keyword.substr(0, 4) == "map_" || keyword == "disp" || keyword == "decal" || keyword == "refl") {
                warn(std::string(keyword) + " in material '" + m.material.name + "' is not used");
            }
            // Ka, Ks, Ns, Ni, illum, Tf, sharpness: no counterpart in a metallic-roughness material.
        }
        for (MtlMaterial& m : materials_) finish(m);
        return std::move(materials_);
    }

private:
    [[noreturn]] void lineFail(const std::string& problem) const { fail(library_, lines_.where() + ": " + problem); }
    void warn(const std::string& problem)
    {
        warnings_.push_back(library_.name + ": " + lines_.where() + ": " + problem);
    }

    double number(std::string_view& rest, const char* what) const
    {
        const std::string_view token = nextToken(rest);
        double value = 0.0;
        if (token.empty()) lineFail(std::string("'") + what + "' without a value");
        if (!parseDouble(token, value) || !std::isfinite(value))
            lineFail(std::string("'") + what + "' value '" + std::string(token.substr(0, 40)) +
                     "' is not a finite number");
        return value;
    }

    // "r [g b]" (one value: grey); "spectral ..." and "xyz ..." are not read (warned).
    glm::dvec3 colour(std::string_view rest)
    {
        std::string_view peek = rest;
        const std::string_view first = nextToken(peek);
        if (first == "spectral" || first == "xyz") {
            warn("colour given as '" + std::string(first) + "' is not read (white used)");
            return glm::dvec3(1.0);
        }
        const double r = number(rest, "colour");
        std::string_view more = rest;
        if (nextToken(more).empty()) return glm::dvec3(r);
        const double g = number(rest, "colour"), b = number(rest, "colour");
        return {r, g, b};
    }

    // "[options] file": options as the MTL spec lists them; the file is the rest of the line
    // (names with spaces exist in the wild).
    MtlTexture texture(std::string_view rest, double* bumpMultiplier)
    {
        MtlTexture t;
        glm::dvec2 offset(0.0), scale(1.0);
        for (;;) {
            std::string_view peek = rest;
            const std::string_view option = nextToken(peek);
            if (option.size() < 2 || option.front() != '-') break;
            rest = peek;
            auto value = [&] { return number(rest, std::string(option).c_str()); };
            auto word = [&] { return nextToken(rest); };
            if (option == "-bm") {
                const double bm = value();
                if (bumpMultiplier) *bumpMultiplier = bm;
            } else if (option == "-clamp") {
                if (word() == "on") t.ref.wrapU = t.ref.wrapV = TextureWrap::ClampToEdge;
            } else if (option == "-blendu" || option == "-blendv" || option == "-cc" || option == "-imfchan" ||
                       option == "-type") {
                word();
            } else if (option == "-boost" || option == "-texres") {
                value();
            } else if (option == "-mm") {
                value(), value();
            } else if (option == "-o" || option == "-s" || option == "-t") {
                glm::dvec3 v = option == "-s" ? glm::dvec3(1.0) : glm::dvec3(0.0);
                for (int c = 0; c < 3; ++c) {  // 1 to 3 numbers
                    std::string_view look = rest;
                    double x;
                    if (!parseDouble(nextToken(look), x) || !std::isfinite(x)) break;
                    v[c] = x;
                    rest = look;
                }
                if (option == "-o") offset = {v.x, v.y};
                if (option == "-s") scale = {v.x, v.y};
                if (option == "-t") warn("texture turbulence (-t) is not used");
            } else {
                warn("unknown texture option '" + std::string(option.substr(0, 40)) + "' skipped");
            }
        }
        t.file = std::string(trim(rest));
        if (t.file.empty()) lineFail("texture statement without a file name");
        // MTL's texture lookup (u, v) -> s * (u, v) + o, with v up; in glTF's uv (v' = 1 - v):
        // u -> s_u u + o_u, v' -> s_v v' + (1 - s_v - o_v).
        t.ref.transform = glm::dmat3(scale.x, 0.0, 0.0, 0.0, scale.y, 0.0, offset.x, 1.0 - scale.y - offset.y, 1.0);
        return t;
    }

    void finish(MtlMaterial& m)
    {
        Material& material = m.material;
        if (!m.baseColor.file.empty()) material.baseColorFactor = glm::dvec4(1.0, 1.0, 1.0, material.baseColorFactor.a);
        if (material.baseColorFactor.a < 1.0) material.alphaMode = AlphaMode::Blend;
        if (!m.emissive.file.empty() && !m.hasEmissiveFactor) material.emissiveFactor = glm::dvec3(1.0);
    }

    const Input& library_;
    LineReader lines_;
    std::vector<std::string>& warnings_;
    std::vector<MtlMaterial> materials_;
};

}  // namespace

std::vector<MtlMaterial> parseMtl(const Input& library, std::vector<std::string>& warnings)
{
    return MtlParser(library, warnings).parse();
}

}  // namespace ngi::mesh_io
