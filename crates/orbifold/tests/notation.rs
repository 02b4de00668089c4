//! Reading and writing signatures: every accepted spelling, every rejected one with its position.

use orbifold::{OrbifoldSymbol, Order, ParseErrorKind, Signature};

fn sig(s: &str) -> Signature {
    s.parse()
        .unwrap_or_else(|e| panic!("{s:?} should parse: {e}"))
}

fn orders(s: &str) -> Vec<String> {
    sig(s).corners().iter().map(ToString::to_string).collect()
}

#[test]
fn accepts_every_documented_spelling() {
    assert_eq!(orders("*"), Vec::<String>::new());
    assert_eq!(orders("*22"), ["2", "2"]);
    assert_eq!(orders("*2333"), ["2", "3", "3", "3"]);
    assert_eq!(
        orders("*23456789(10)(11)"),
        ["2", "3", "4", "5", "6", "7", "8", "9", "10", "11"]
    );
    assert_eq!(orders("*∞∞∞"), ["∞", "∞", "∞"]);
    assert_eq!(orders("*222infinf"), ["2", "2", "2", "∞", "∞"]);
    assert_eq!(orders("*(inf)(inf)(inf)"), ["∞", "∞", "∞"]);
    assert_eq!(orders("*(INF)(∞)(infinity)"), ["∞", "∞", "∞"]);
    assert_eq!(orders("*(3/2)33"), ["3/2", "3", "3"]);
    assert_eq!(orders("*(1.5)33"), ["3/2", "3", "3"]);
    assert_eq!(orders("*( 6 / 4 )33"), ["3/2", "3", "3"]);
    assert_eq!(orders("*(4/2)33"), ["2", "3", "3"]);
    assert_eq!(orders("*(2.0)33"), ["2", "3", "3"]);
}

#[test]
fn whitespace_around_and_between_items_is_ignored() {
    assert_eq!(sig("  *2333\n"), sig("*2333"));
    assert_eq!(sig("\t* 2 3 3 3 "), sig("*2333"));
}

#[test]
fn corners_of_order_one_are_removed() {
    assert_eq!(sig("*11"), sig("*"));
    assert_eq!(sig("*1"), sig("*"));
    assert_eq!(sig("*2(1)2"), sig("*22"));
    assert_eq!(sig("*(1/1)(2/2)"), sig("*"));
}

#[test]
fn display_round_trips() {
    for s in [
        "*",
        "*22",
        "*2333",
        "*23456789(10)(11)",
        "*∞∞∞",
        "*222∞∞",
        "*(3/2)33",
        "*(100)(1000000)2",
    ] {
        assert_eq!(sig(s).to_string(), s);
        assert_eq!(sig(&sig(s).to_string()), sig(s));
    }
    assert_eq!(sig("*(12)").to_string(), "*(12)");
    assert_eq!(sig("*(1.25)(1.25)").to_string(), "*(5/4)(5/4)");
}

fn error(s: &str) -> (usize, ParseErrorKind, String) {
    let e = s.parse::<Signature>().expect_err(s);
    (e.position(), e.kind().clone(), e.to_string())
}

#[test]
fn malformed_input_names_position_and_reason() {
    let (pos, kind, msg) = error("*(");
    assert_eq!((pos, kind), (2, ParseErrorKind::Unclosed));
    assert!(
        msg.contains("position 2") && msg.contains("never closed"),
        "{msg}"
    );

    let (pos, kind, msg) = error("*0");
    assert_eq!((pos, kind), (2, ParseErrorKind::Zero));
    assert!(msg.contains("order of 0"), "{msg}");

    let (pos, kind, _) = error("*-3");
    assert_eq!((pos, kind), (2, ParseErrorKind::Negative));

    let (pos, kind, msg) = error("*2q");
    assert_eq!((pos, kind), (3, ParseErrorKind::UnexpectedChar('q')));
    assert!(msg.contains("'q'"), "{msg}");

    let (pos, kind, msg) = error("*(2/0)");
    assert_eq!((pos, kind), (2, ParseErrorKind::DivisionByZero));
    assert!(msg.contains("divides by zero"), "{msg}");

    let (pos, kind, msg) = error("");
    assert_eq!((pos, kind), (1, ParseErrorKind::Empty));
    assert!(msg.contains("empty"), "{msg}");

    assert_eq!(error("   ").1, ParseErrorKind::Empty);
    assert_eq!(error("*()").1, ParseErrorKind::EmptyParentheses);
    assert_eq!(error("*(abc)").1, ParseErrorKind::NotANumber("abc".into()));
    assert_eq!(error("*(1/2)3").1, ParseErrorKind::BelowOne("1/2".into()));
    assert_eq!(error("*(0.5)3").1, ParseErrorKind::BelowOne("0.5".into()));
    assert_eq!(error("*(-2)").1, ParseErrorKind::Negative);
    assert_eq!(error("*(99999999999999999999)").1, ParseErrorKind::TooLarge);
    assert_eq!(
        error("*(1.2.3)").1,
        ParseErrorKind::NotANumber("1.2.3".into())
    );
}

#[test]
fn positions_count_characters_not_bytes() {
    // `∞` is three bytes in UTF-8 but one character.
    let (pos, _, _) = error("*∞∞q");
    assert_eq!(pos, 4);
    let (pos, _, _) = error("  *2(");
    assert_eq!(pos, 5);
}

#[test]
fn snippet_points_at_the_problem() {
    let e = "*23q5".parse::<Signature>().unwrap_err();
    assert_eq!(e.snippet(), "  *23q5\n     ^");
    let e = "*2(3/0)".parse::<Signature>().unwrap_err();
    assert_eq!(e.snippet(), "  *2(3/0)\n    ^^^^^");
}

#[test]
fn conway_symbols_are_not_kaleidoscopic_signatures() {
    for s in ["632", "4*2", "2*22", "**", "*×", "o", "22×"] {
        let (_, kind, msg) = error(s);
        assert!(
            matches!(kind, ParseErrorKind::NotKaleidoscopic(_)),
            "{s}: {kind:?}"
        );
        assert!(msg.contains("kaleidoscopic"), "{msg}");
        assert!(
            s.parse::<OrbifoldSymbol>().is_ok(),
            "{s} is valid Conway notation"
        );
    }
}

#[test]
fn conway_notation_structure() {
    let s: OrbifoldSymbol = "o".parse().unwrap();
    assert_eq!(s.handles(), 1);
    let s: OrbifoldSymbol = "2*22".parse().unwrap();
    assert_eq!(s.cones(), [Order::integer(2)]);
    assert_eq!(s.boundaries(), [vec![Order::integer(2), Order::integer(2)]]);
    let s: OrbifoldSymbol = "22x".parse().unwrap();
    assert_eq!((s.cones().len(), s.crosscaps()), (2, 1));
    let s: OrbifoldSymbol = "**".parse().unwrap();
    assert_eq!(s.boundaries().len(), 2);
    let s: OrbifoldSymbol = "××".parse().unwrap();
    assert_eq!(s.crosscaps(), 2);
    assert_eq!("22222".parse::<OrbifoldSymbol>().unwrap().cones().len(), 5);
    assert_eq!("1".parse::<OrbifoldSymbol>().unwrap().to_string(), "1");
}

#[test]
fn conway_notation_errors() {
    let e = "2o".parse::<OrbifoldSymbol>().unwrap_err();
    assert_eq!(
        (e.position(), e.kind().clone()),
        (2, ParseErrorKind::HandleNotFirst)
    );
    let e = "×2".parse::<OrbifoldSymbol>().unwrap_err();
    assert_eq!(e.position(), 2);
    assert!(matches!(e.kind(), ParseErrorKind::AfterCrossCap(_)));
    let e = "×*".parse::<OrbifoldSymbol>().unwrap_err();
    assert!(matches!(e.kind(), ParseErrorKind::AfterCrossCap(_)));
    let e = "(3/2)*".parse::<OrbifoldSymbol>().unwrap_err();
    assert_eq!(
        (e.position(), e.kind().clone()),
        (
            1,
            ParseErrorKind::NonIntegerOutsideKaleidoscope("3/2".into())
        )
    );
    let e = "*(5/2)*2".parse::<OrbifoldSymbol>().unwrap_err();
    assert_eq!(e.position(), 2);
}
