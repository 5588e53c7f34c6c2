//! The public face of `brdf-simd`: spellings, serde, and a process-wide cell in a `static`.

use brdf_simd::{Kernel, KernelCell, cpu};

static CHOICE: KernelCell = KernelCell::new();

/// The serde spelling is the lowercase name (spec files and stored results use it), and a
/// misspelt kernel in a document is an error naming the value.
#[test]
fn serde_uses_the_lowercase_names() {
    for k in Kernel::ALL {
        let json = serde_json::to_string(&k).unwrap();
        assert_eq!(json, format!("\"{}\"", k.name()));
        assert_eq!(serde_json::from_str::<Kernel>(&json).unwrap(), k);
    }
    let err = serde_json::from_str::<Kernel>("\"avx1024\"").unwrap_err();
    assert!(err.to_string().contains("avx1024"), "{err}");
}

/// A `static` cell reads as the best kernel until set, then as what was set; the available
/// kernels follow the cached detection.
#[test]
fn a_static_cell_follows_set() {
    assert_eq!(CHOICE.get(), Kernel::best());
    assert_eq!(CHOICE.set(Kernel::Portable), Ok(Kernel::Portable));
    assert_eq!(CHOICE.get(), Kernel::Portable);
    assert_eq!(Kernel::Avx512.is_available(), cpu().avx512);
    assert_eq!(Kernel::Avx2.is_available(), cpu().avx2_fma);
    assert_eq!(Kernel::default(), Kernel::Auto);
}
