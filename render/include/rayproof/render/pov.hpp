// rayproof/render/pov.hpp — a scene as POV-Ray 3.7 scene-description text, for rendering the
// same scene with POV-Ray side by side. What POV-Ray cannot express exactly is written as
// the nearest equivalent with a comment (the light attenuation law, RGB specular
// coefficients, an ambient coefficient where the diffuse colour is zero).
#pragma once

#include <rayproof/render/scene.hpp>

#include <string>
#include <vector>

namespace rayproof::render {

struct PovScene {
    std::string text;                  // the POV-Ray 3.7 scene
    std::vector<std::string> inexact;  // what it does not render as rayproof does, one line each
};

// source_name goes into the header comment only.
PovScene to_pov(const Scene& scene, const std::string& source_name = "");
std::string export_pov(const Scene& scene, const std::string& source_name = "");  // to_pov(...).text

}  // namespace rayproof::render
