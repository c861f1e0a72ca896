// The enum name tables: every name parses back to its value, unknown names list every choice.
#include "beamtrace/core/name_table.hpp"

#include <gtest/gtest.h>

#include <string>

#include "beamtrace/heightfield/color_mode.hpp"
#include "beamtrace/physics/atmosphere.hpp"
#include "beamtrace/physics/pulse.hpp"
#include "beamtrace/physics/range_equation.hpp"
#include "beamtrace/sensor/line_scanner.hpp"

namespace beamtrace {
namespace {

enum class Fruit { apple, pear, plum };
constexpr NameTable<Fruit, 3> kFruits{
    "fruit", {{{Fruit::apple, "apple"}, {Fruit::pear, "pear"}, {Fruit::plum, "plum"}}}};

TEST(NameTable, ParsesEveryNameAndWritesItBack) {
    for (const auto& e : kFruits.entries()) {
        EXPECT_EQ(kFruits.parse(e.name), e.value);
        EXPECT_EQ(kFruits.to_string(e.value), e.name);
    }
    static_assert(kFruits.find("pear") == Fruit::pear);
    static_assert(!kFruits.find("Pear").has_value());
    static_assert(kFruits.to_string(static_cast<Fruit>(7)) == "?");
}

TEST(NameTable, UnknownNameListsTheChoices) {
    try {
        (void)kFruits.parse("kiwi");
        FAIL() << "kiwi parsed";
    } catch (const ConfigError& e) {
        EXPECT_STREQ(e.what(), "unknown fruit 'kiwi' (expected apple, pear or plum)");
    }
    EXPECT_EQ(kFruits.choices(), "apple | pear | plum");
    EXPECT_EQ(join_alternatives(std::array<std::string_view, 1>{"one"}), "one");
    EXPECT_EQ(join_alternatives(std::array<std::string_view, 2>{"a", "b"}), "a or b");
}

/// parse(to_string(v)) == v for every value of a library enum, and a wrong name throws.
template <class Enum, class Parse>
void round_trips(std::initializer_list<Enum> values, Parse parse, const char* what) {
    for (const Enum v : values) {
        EXPECT_EQ(parse(to_string(v)), v) << what;
    }
    try {
        (void)parse("nonsense");
        ADD_FAILURE() << what << ": nonsense parsed";
    } catch (const ConfigError& e) {
        EXPECT_NE(std::string(e.what()).find(std::string("unknown ") + what + " 'nonsense'"),
                  std::string::npos)
            << e.what();
    }
}

TEST(NameTable, LibraryEnumsRoundTrip) {
    round_trips({ScanWaveform::sawtooth, ScanWaveform::sinusoid, ScanWaveform::triangle},
                parse_scan_waveform, "scan waveform");
    round_trips({ReturnMode::first, ReturnMode::last, ReturnMode::strongest, ReturnMode::all},
                parse_return_mode, "return mode");
    round_trips({ExtinctionModel::kim, ExtinctionModel::kruse}, parse_extinction_model,
                "extinction model");
    round_trips({IntensityScale::linear, IntensityScale::logarithmic}, parse_intensity_scale,
                "intensity scale");
    for (const ColorMode m :
         {ColorMode::height, ColorMode::rgb, ColorMode::intensity, ColorMode::classification}) {
        EXPECT_EQ(parse_color_mode(color_mode_name(m)), m);
    }
    EXPECT_THROW((void)parse_color_mode("hue"), ConfigError);
}

}  // namespace
}  // namespace beamtrace
