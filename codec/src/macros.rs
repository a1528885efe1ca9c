//! Macros the generated code uses for its most repeated shapes. They implement both
//! encodings (UPER and JER) of a type, so they sit above `uper` and `jer`.

/// Methods and trait impls of a constrained INTEGER newtype `$name($prim)` in `$lb..=$ub`.
macro_rules! constrained_int {
    ($name:ident, $prim:ty, $lb:literal, $ub:literal, $path:literal) => {
        impl $name {
            /// Smallest value the type allows.
            pub const MIN: $prim = $lb;
            /// Largest value the type allows.
            pub const MAX: $prim = $ub;
            /// `v` when it lies in `MIN..=MAX`.
            #[allow(unreachable_patterns)]
            pub const fn new(v: $prim) -> ::core::option::Option<Self> {
                match v {
                    $lb..=$ub => ::core::option::Option::Some(Self(v)),
                    _ => ::core::option::Option::None,
                }
            }
            /// The number.
            pub const fn get(self) -> $prim {
                self.0
            }
        }
        impl ::core::convert::From<$name> for $prim {
            fn from(v: $name) -> $prim {
                v.0
            }
        }
        impl ::core::convert::TryFrom<$prim> for $name {
            type Error = $crate::uper::OutOfRange;
            fn try_from(v: $prim) -> ::core::result::Result<Self, Self::Error> {
                Self::new(v).ok_or($crate::uper::OutOfRange)
            }
        }
        impl $crate::uper::Placeholder for $name {
            fn placeholder() -> Self {
                Self($lb)
            }
        }
        #[cfg(feature = "alloc")]
        impl $crate::__private::ConstPlaceholder for $name {
            const PLACEHOLDER: Self = Self($lb);
        }
        #[cfg(feature = "jer")]
        impl $crate::jer::Jer for $name {
            fn write_jer(&self, out: &mut $crate::jer::JerWriter) {
                out.int(self.0 as i64);
            }
            fn read_jer(v: &$crate::jer::Value) -> $crate::jer::JerResult<Self> {
                ::core::result::Result::Ok(Self($crate::__private::jer::int(v, $lb, $ub)? as $prim))
            }
        }
        #[cfg(feature = "_random")]
        impl $crate::uper::random::Random for $name {
            fn random(g: &mut $crate::uper::random::Gen) -> Self {
                Self(g.range($lb, $ub) as $prim)
            }
        }
        impl $crate::uper::Uper for $name {
            const PATH: &'static str = $path;
            const MAX_UPER_BITS: ::core::option::Option<u64> = ::core::option::Option::Some(
                64 - (($ub as i128 - $lb as i128) as u64).leading_zeros() as u64,
            );
            #[inline]
            fn decode_body_into(
                r: &mut $crate::uper::Reader<'_>,
                out: &mut Self,
            ) -> $crate::uper::DecodeResult<()> {
                *out = Self(r.read_constrained($lb, $ub)? as $prim);
                ::core::result::Result::Ok(())
            }
            #[inline]
            fn encode_body(&self, w: &mut $crate::uper::Writer<'_>) -> $crate::uper::EncodeResult {
                w.write_constrained(self.0 as i64, $lb, $ub)
            }
        }
    };
}

/// `Deref`/`DerefMut` of a newtype `$name` to its storage `$target`.
macro_rules! newtype_deref {
    ($name:ident, $target:ty) => {
        impl ::core::ops::Deref for $name {
            type Target = $target;
            fn deref(&self) -> &$target {
                &self.0
            }
        }
        impl ::core::ops::DerefMut for $name {
            fn deref_mut(&mut self) -> &mut $target {
                &mut self.0
            }
        }
    };
}

pub(crate) use {constrained_int, newtype_deref};
