//! Orbifold notation: `Signature` (kaleidoscopic `*k₁…k_N`) and `OrbifoldSymbol` (any Conway
//! symbol) from arbitrary text.
//!
//! Never panics, and on success:
//! - the printed form reads back to the same value (`Display` ∘ `FromStr` is the identity),
//!   for the signature as written and for its canonical form;
//! - the canonical form is canonical and idempotent and has the same Euler characteristic;
//! - `geometry()` agrees with the sign of `euler_characteristic()`;
//! - a string that is a `Signature` is also an `OrbifoldSymbol`, and the symbol's kaleidoscopic
//!   signature and Euler characteristic are the signature's.

#![no_main]

use libfuzzer_sys::fuzz_target;
use orbifold::{OrbifoldSymbol, Signature};

fuzz_target!(|data: &[u8]| {
    let Ok(s) = std::str::from_utf8(data) else {
        return;
    };

    let signature = s.parse::<Signature>();
    if let Err(e) = &signature {
        // The messages must be printable whatever the input.
        let _ = (e.to_string(), e.snippet(), e.position());
    }
    let symbol = s.parse::<OrbifoldSymbol>();
    if let Err(e) = &symbol {
        let _ = (e.to_string(), e.snippet(), e.position());
    }

    if let Ok(sig) = &signature {
        check_signature(sig);
        let symbol = symbol
            .as_ref()
            .unwrap_or_else(|e| panic!("{s:?} is a Signature but not an OrbifoldSymbol: {e}"));
        assert_eq!(symbol.as_kaleidoscopic().as_ref(), Some(sig), "{s:?}");
        assert_eq!(
            symbol.euler_characteristic(),
            sig.euler_characteristic(),
            "{s:?}: symbol and signature disagree on χ"
        );
        assert_eq!(&OrbifoldSymbol::from(sig.clone()), symbol, "{s:?}");
    }
    if let Ok(symbol) = &symbol {
        check_symbol(symbol);
    }
});

fn check_signature(sig: &Signature) {
    let text = sig.to_string();
    let chi = sig.euler_characteristic();
    let _ = chi.to_string();
    assert_eq!(sig.geometry(), chi.geometry(), "{text}: geometry vs χ");
    let _ = sig.kind();
    let _ = (
        sig.reason(),
        sig.area(),
        sig.group_order(),
        sig.free_parameters(),
    );
    let _ = (sig.angle_sum(), sig.family(), sig.is_buildable());

    let again: Signature = text
        .parse()
        .unwrap_or_else(|e| panic!("the printed signature {text:?} does not parse: {e}"));
    assert_eq!(&again, sig, "{text:?} reads back differently");

    let canonical = sig.canonical();
    let canonical_text = canonical.to_string();
    assert!(
        canonical.is_canonical(),
        "{canonical_text} is not canonical"
    );
    assert_eq!(
        canonical.canonical(),
        canonical,
        "canonical() is not idempotent"
    );
    assert_eq!(
        canonical.euler_characteristic(),
        chi,
        "{text} and its canonical form {canonical_text} differ in χ"
    );
    let again: Signature = canonical_text.parse().unwrap_or_else(|e| {
        panic!("the canonical signature {canonical_text:?} does not parse: {e}")
    });
    assert_eq!(
        again, canonical,
        "{canonical_text:?} reads back differently"
    );
}

fn check_symbol(symbol: &OrbifoldSymbol) {
    let text = symbol.to_string();
    let chi = symbol.euler_characteristic();
    let _ = chi.to_string();
    assert_eq!(symbol.geometry(), chi.geometry(), "{text}: geometry vs χ");
    let _ = (
        symbol.reason(),
        symbol.is_bad(),
        symbol.group_order(),
        symbol.area(),
    );
    let _ = (
        symbol.free_parameters(),
        symbol.symmetry_group(),
        symbol.features(),
    );
    let _ = symbol.preserves_orientation();

    let again: OrbifoldSymbol = text
        .parse()
        .unwrap_or_else(|e| panic!("the printed symbol {text:?} does not parse: {e}"));
    assert_eq!(&again, symbol, "{text:?} reads back differently");

    let canonical = symbol.canonical();
    let canonical_text = canonical.to_string();
    assert_eq!(
        canonical.canonical(),
        canonical,
        "canonical() of {text} is not idempotent"
    );
    assert_eq!(
        canonical.euler_characteristic(),
        chi,
        "{text} and its canonical form {canonical_text} differ in χ"
    );
    let again: OrbifoldSymbol = canonical_text
        .parse()
        .unwrap_or_else(|e| panic!("the canonical symbol {canonical_text:?} does not parse: {e}"));
    assert_eq!(
        again, canonical,
        "{canonical_text:?} reads back differently"
    );
}
