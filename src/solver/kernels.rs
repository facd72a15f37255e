//! [`Kernels`]: which compiled form of the solver's hot loops a step runs.
//! Every choice gives the same bits; the choice is speed only.
use super::soft_contact::Compiled;

/// The kernels of the soft step's contact passes
/// ([`Space::set_kernels`](crate::space::Space::set_kernels)).
///
/// The wide kernels solve four manifolds of one color at a time in
/// integer lanes, with exactly the bits of the scalar kernels (a lane that
/// leaves their window is run again by the scalar kernel). They pay only
/// in AVX2 instructions: for the x86_64 baseline (SSE2), for other
/// processors and for wasm (even with its 128-bit SIMD, two lanes an
/// instruction) they are slower than the scalar ones
/// (`docs/performance.md`, "Wide kernels" and "In the browser"), so
/// [`Kernels::Auto`] runs them only where the processor has AVX2, and
/// only in optimised builds. Configuration, not state: never saved in a
/// snapshot.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Kernels {
    /// The fastest measured on this processor: the wide kernels in AVX2
    /// instructions where it has AVX2 (a runtime check), the scalar ones
    /// elsewhere. The default. A build with debug assertions (an
    /// unoptimised build, as a rule) runs the scalar ones: unoptimised,
    /// every lane operation is a call and the wide kernels run about 60
    /// times slower.
    #[default]
    Auto,
    /// The scalar kernels only.
    Scalar,
    /// The wide kernels, compiled for AVX2 where the processor has it (a
    /// runtime check), for the build's instruction set elsewhere.
    Wide,
    /// The wide kernels compiled for the build's instruction set, even on
    /// a processor with AVX2: for tests that check their bits everywhere.
    Portable,
}

impl Kernels {
    /// How the wide kernels run (`None`: the scalar ones run).
    pub(crate) fn wide(self) -> Option<Compiled> {
        match self {
            Kernels::Scalar => None,
            Kernels::Auto if cfg!(debug_assertions) => None,
            Kernels::Auto | Kernels::Wide if tamias2d_simd::has_avx2() => Some(Compiled::Avx2),
            Kernels::Auto => None,
            Kernels::Wide | Kernels::Portable => Some(Compiled::Portable),
        }
    }

    /// What runs on this processor, for reports: `"scalar"`, `"avx2"` or
    /// `"portable"`.
    pub fn describe(self) -> &'static str {
        match self.wide() {
            Some(Compiled::Avx2) => "avx2",
            Some(Compiled::Portable) => "portable",
            None => "scalar",
        }
    }
}
