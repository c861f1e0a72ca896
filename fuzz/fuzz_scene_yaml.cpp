// libFuzzer target: scene files (parse_scene_spec on the input as YAML text), and the scene
// builder on those that hold only primitives (spheres, planes: no file to load). The scene's
// folder holds an empty model.obj and dem.asc, so that seeds naming them pass the existence
// checks of the parser.
#include <algorithm>
#include <cstddef>
#include <cstdint>

#include "beamtrace/scene/scene_builder.hpp"
#include "beamtrace/scene/scene_spec.hpp"
#include "fuzz_input.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    static const bool files_made = [] {
        const std::uint8_t none = 0;
        (void)beamtrace::fuzz::write_input(&none, 0, "model.obj");
        (void)beamtrace::fuzz::write_input(&none, 0, "dem.asc");
        return true;
    }();
    (void)files_made;
    const auto text = beamtrace::fuzz::as_text(data, size);
    const auto source = beamtrace::fuzz::scratch_dir() / "scene.yaml";
    return beamtrace::fuzz::run_guarded([&] {
        const beamtrace::SceneSpec spec = beamtrace::parse_scene_spec(text, source);
        const bool primitives_only =
            std::all_of(spec.parts.begin(), spec.parts.end(),
                        [](const auto& part) { return part.file.empty(); });
        if (primitives_only) {
            (void)beamtrace::build_scene(spec);
        }
    });
}
