// Small 3-vector value type used for positions and directions.
#pragma once

#include <cmath>
#include <cstddef>

namespace beamtrace {

template <typename T>
struct Vec3 {
    T x{}, y{}, z{};

    constexpr Vec3() = default;
    constexpr Vec3(T x_, T y_, T z_) : x(x_), y(y_), z(z_) {}
    template <typename U>
    constexpr explicit Vec3(const Vec3<U>& o)
        : x(static_cast<T>(o.x)), y(static_cast<T>(o.y)), z(static_cast<T>(o.z)) {}

    [[nodiscard]] constexpr T operator[](std::size_t i) const {
        return i == 0 ? x : (i == 1 ? y : z);
    }
    [[nodiscard]] constexpr T& operator[](std::size_t i) { return i == 0 ? x : (i == 1 ? y : z); }

    constexpr Vec3& operator+=(const Vec3& o) {
        x += o.x;
        y += o.y;
        z += o.z;
        return *this;
    }
    constexpr Vec3& operator-=(const Vec3& o) {
        x -= o.x;
        y -= o.y;
        z -= o.z;
        return *this;
    }
    constexpr Vec3& operator*=(T s) {
        x *= s;
        y *= s;
        z *= s;
        return *this;
    }
    friend constexpr bool operator==(const Vec3&, const Vec3&) = default;
};

template <typename T>
[[nodiscard]] constexpr Vec3<T> operator+(Vec3<T> a, const Vec3<T>& b) {
    return a += b;
}
template <typename T>
[[nodiscard]] constexpr Vec3<T> operator-(Vec3<T> a, const Vec3<T>& b) {
    return a -= b;
}
template <typename T>
[[nodiscard]] constexpr Vec3<T> operator-(const Vec3<T>& a) {
    return {-a.x, -a.y, -a.z};
}
template <typename T>
[[nodiscard]] constexpr Vec3<T> operator*(Vec3<T> a, T s) {
    return a *= s;
}
template <typename T>
[[nodiscard]] constexpr Vec3<T> operator*(T s, Vec3<T> a) {
    return a *= s;
}
template <typename T>
[[nodiscard]] constexpr T dot(const Vec3<T>& a, const Vec3<T>& b) {
    return a.x * b.x + a.y * b.y + a.z * b.z;
}
template <typename T>
[[nodiscard]] constexpr Vec3<T> cross(const Vec3<T>& a, const Vec3<T>& b) {
    return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
template <typename T>
[[nodiscard]] inline T length(const Vec3<T>& a) {
    return std::sqrt(dot(a, a));
}
template <typename T>
[[nodiscard]] inline Vec3<T> normalize(const Vec3<T>& a) {
    return a * (T(1) / length(a));
}
template <typename T>
[[nodiscard]] constexpr Vec3<T> min(const Vec3<T>& a, const Vec3<T>& b) {
    return {a.x < b.x ? a.x : b.x, a.y < b.y ? a.y : b.y, a.z < b.z ? a.z : b.z};
}
template <typename T>
[[nodiscard]] constexpr Vec3<T> max(const Vec3<T>& a, const Vec3<T>& b) {
    return {a.x > b.x ? a.x : b.x, a.y > b.y ? a.y : b.y, a.z > b.z ? a.z : b.z};
}

using Vec3f = Vec3<float>;
using Vec3d = Vec3<double>;

}  // namespace beamtrace
