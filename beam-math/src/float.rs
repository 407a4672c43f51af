//! The one place that chooses between `std` and `libm` float functions, so that call sites carry no
//! `cfg`. Implemented for `f32` and `f64`.

/// Float functions that `core` does not provide on every target.
pub trait Float: Copy {
    /// Square root.
    #[must_use]
    fn sqrt_(self) -> Self;
    /// Sine.
    #[must_use]
    fn sin_(self) -> Self;
    /// Cosine.
    #[must_use]
    fn cos_(self) -> Self;
    /// Tangent.
    #[must_use]
    fn tan_(self) -> Self;
    /// Arc sine.
    #[must_use]
    fn asin_(self) -> Self;
    /// Arc cosine.
    #[must_use]
    fn acos_(self) -> Self;
    /// Arc tangent.
    #[must_use]
    fn atan_(self) -> Self;
    /// Four-quadrant arc tangent of `self / x`.
    #[must_use]
    fn atan2_(self, x: Self) -> Self;
    /// Natural exponential.
    #[must_use]
    fn exp_(self) -> Self;
    /// Cube root.
    #[must_use]
    fn cbrt_(self) -> Self;
    /// Error function (always from libm: std has none).
    #[must_use]
    fn erf_(self) -> Self;
}

macro_rules! impl_float {
    ($t:ty, $sqrt:ident, $sin:ident, $cos:ident, $tan:ident, $asin:ident, $acos:ident, $atan:ident,
     $atan2:ident, $exp:ident, $cbrt:ident, $erf:ident) => {
        impl Float for $t {
            #[inline]
            fn sqrt_(self) -> Self {
                #[cfg(feature = "std")]
                return self.sqrt();
                #[cfg(not(feature = "std"))]
                return libm::$sqrt(self);
            }
            #[inline]
            fn sin_(self) -> Self {
                #[cfg(feature = "std")]
                return self.sin();
                #[cfg(not(feature = "std"))]
                return libm::$sin(self);
            }
            #[inline]
            fn cos_(self) -> Self {
                #[cfg(feature = "std")]
                return self.cos();
                #[cfg(not(feature = "std"))]
                return libm::$cos(self);
            }
            #[inline]
            fn tan_(self) -> Self {
                #[cfg(feature = "std")]
                return self.tan();
                #[cfg(not(feature = "std"))]
                return libm::$tan(self);
            }
            #[inline]
            fn asin_(self) -> Self {
                #[cfg(feature = "std")]
                return self.asin();
                #[cfg(not(feature = "std"))]
                return libm::$asin(self);
            }
            #[inline]
            fn acos_(self) -> Self {
                #[cfg(feature = "std")]
                return self.acos();
                #[cfg(not(feature = "std"))]
                return libm::$acos(self);
            }
            #[inline]
            fn atan_(self) -> Self {
                #[cfg(feature = "std")]
                return self.atan();
                #[cfg(not(feature = "std"))]
                return libm::$atan(self);
            }
            #[inline]
            fn atan2_(self, x: Self) -> Self {
                #[cfg(feature = "std")]
                return self.atan2(x);
                #[cfg(not(feature = "std"))]
                return libm::$atan2(self, x);
            }
            #[inline]
            fn exp_(self) -> Self {
                #[cfg(feature = "std")]
                return self.exp();
                #[cfg(not(feature = "std"))]
                return libm::$exp(self);
            }
            #[inline]
            fn cbrt_(self) -> Self {
                #[cfg(feature = "std")]
                return self.cbrt();
                #[cfg(not(feature = "std"))]
                return libm::$cbrt(self);
            }
            #[inline]
            fn erf_(self) -> Self {
                libm::$erf(self)
            }
        }
    };
}

impl_float!(f32, sqrtf, sinf, cosf, tanf, asinf, acosf, atanf, atan2f, expf, cbrtf, erff);
impl_float!(f64, sqrt, sin, cos, tan, asin, acos, atan, atan2, exp, cbrt, erf);
