// The Extra Bytes VLR (LAS 1.4 R15 section 2.16, Table 24): 192-byte descriptors at the
// documented offsets, read back by las_extra_bytes_descriptors; values scaled as they say.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "beamtrace/core/error.hpp"
#include "beamtrace/io/las_extra_bytes.hpp"
#include "beamtrace/io/las_reader.hpp"
#include "beamtrace/io/point_attributes.hpp"
#include "test_support.hpp"

namespace beamtrace {
namespace {

template <class T>
T at(const std::vector<std::uint8_t>& b, std::size_t offset) {
    T v{};
    std::memcpy(&v, b.data() + offset, sizeof(T));
    return v;
}

TEST(LasExtraBytes, DescriptorsSitAtTheOffsetsOfTable24) {
    LasExtraBytesDescriptor range = point_attribute_descriptor(PointAttribute::range);
    LasExtraBytesDescriptor width = point_attribute_descriptor(PointAttribute::echo_width);
    const LasExtraBytesDescriptor both[] = {range, width};
    const LasVlr vlr = las_extra_bytes_vlr(both);
    EXPECT_EQ(vlr.user_id, "LASF_Spec");
    EXPECT_EQ(vlr.record_id, 4);
    ASSERT_EQ(vlr.data.size(), 2u * 192u);
    const auto& b = vlr.data;
    EXPECT_EQ(b[2], 5) << "data_type uint32";
    EXPECT_EQ(b[3], 8) << "options: scale";
    EXPECT_EQ(std::string(reinterpret_cast<const char*>(b.data() + 4)), "range_m");
    EXPECT_EQ(at<double>(b, 112), 0.001) << "scale";
    EXPECT_EQ(at<double>(b, 136), 0.0) << "offset";
    EXPECT_EQ(std::string(reinterpret_cast<const char*>(b.data() + 160)),
              "range from beam origin, m");
    EXPECT_EQ(b[192 + 2], 3) << "data_type uint16";
    EXPECT_EQ(b[192 + 3], 1 | 8) << "options: no_data, scale";
    EXPECT_EQ(at<std::uint64_t>(b, 192 + 40), 65535u) << "no_data, unsigned slot";
    EXPECT_EQ(at<double>(b, 192 + 112), 0.01);
    const LasVlr vlrs[] = {vlr};
    const auto back = las_extra_bytes_descriptors(vlrs);
    ASSERT_EQ(back.size(), 2u);
    EXPECT_EQ(back[0].name, "range_m");
    EXPECT_EQ(back[1].no_data, 65535.0);
    EXPECT_EQ(las_extra_bytes_size(back), 6u);
}

TEST(LasExtraBytes, AttributesRoundToTheirScaleAndClamp) {
    const PointAttribute all[] = {PointAttribute::range, PointAttribute::incidence_angle,
                                  PointAttribute::echo_width, PointAttribute::beam,
                                  PointAttribute::object_id};
    std::vector<LasExtraBytesDescriptor> fields;
    for (const PointAttribute a : all) {
        fields.push_back(point_attribute_descriptor(a));
    }
    std::vector<std::uint8_t> bytes(las_extra_bytes_size(fields));
    ASSERT_EQ(bytes.size(), 14u);
    encode_point_attributes(all, {123.4564, 29.996, 4.004, 17, 70000}, bytes.data());
    EXPECT_DOUBLE_EQ(las_extra_bytes_value(fields, 0, bytes), 123.456);
    EXPECT_DOUBLE_EQ(las_extra_bytes_value(fields, 1, bytes), 30.0);
    EXPECT_DOUBLE_EQ(las_extra_bytes_value(fields, 2, bytes), 4.0);
    EXPECT_EQ(las_extra_bytes_value(fields, 3, bytes), 17.0);
    EXPECT_EQ(las_extra_bytes_value(fields, 4, bytes), 70000.0);
    // An unknown echo width is the no-data value; a huge one stops a step below it.
    encode_point_attributes(all, {0, 0, std::nan(""), 0, 0}, bytes.data());
    EXPECT_EQ(at<std::uint16_t>(bytes, 6), 65535);
    encode_point_attributes(all, {-1, 0, 1e9, 0, 0}, bytes.data());
    EXPECT_EQ(at<std::uint16_t>(bytes, 6), 65534);
    EXPECT_EQ(at<std::uint32_t>(bytes, 0), 0u) << "negative ranges clamp to 0";
}

TEST(LasExtraBytes, ReadsTheDescriptorsOfAThirdPartyFile) {
    // Written by LAStools, with two Extra Bytes VLRs of one descriptor each.
    const LasReader reader(test::shared_data("las/derived/las_with_several_extra_byte_bloc.las"));
    const auto d = las_extra_bytes_descriptors(reader.vlrs());
    ASSERT_EQ(d.size(), 2u);
    EXPECT_EQ(d[0].name, "Deviation");
    EXPECT_EQ(d[0].data_type, LasExtraType::u16);
    EXPECT_EQ(d[0].options, 7);
    EXPECT_EQ(d[0].description, "Pulse shape deviation");
    EXPECT_EQ(d[1].name, "confidence");
    EXPECT_EQ(d[1].data_type, LasExtraType::u8);
    EXPECT_EQ(las_extra_bytes_size(d), reader.header().extra_bytes_per_point());
}

TEST(LasExtraBytes, BadVlrsAndNamesThrow) {
    LasVlr bad;
    bad.user_id = "LASF_Spec";
    bad.record_id = 4;
    bad.data.assign(100, 0);
    const LasVlr vlrs[] = {bad};
    EXPECT_THROW((void)las_extra_bytes_descriptors(vlrs), InputError);
    LasExtraBytesDescriptor d;
    d.name = std::string(32, 'x');
    const LasExtraBytesDescriptor one[] = {d};
    EXPECT_THROW((void)las_extra_bytes_vlr(one), ConfigError);
    EXPECT_FALSE(point_attribute_named("speed").has_value());
    EXPECT_EQ(point_attribute_named("echo_width"), PointAttribute::echo_width);
}

}  // namespace
}  // namespace beamtrace
