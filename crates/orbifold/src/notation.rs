//! Reading orbifold notation: Conway's symbols, of which kaleidoscopic signatures are a part.
//!
//! The grammar, item by item (whitespace between items is ignored):
//!
//! | item | meaning |
//! |---|---|
//! | `o` | a handle ("wonder"); written first |
//! | `2`…`9`, `(12)`, `∞`, `inf`, `(inf)` | an order: a cone point before the first `*`, a corner after it |
//! | `(3/2)`, `(1.5)` | a non-integer order (non-orbifold corner; kaleidoscopic signatures only) |
//! | `*` | a mirror boundary; the orders that follow are its corners |
//! | `×` or `x` | a cross-cap ("miracle"); written last |
//!
//! Orders equal to 1 are removed: `*11` is `*`.

use std::fmt;

use crate::order::Order;

/// What went wrong while reading a signature.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum ParseErrorKind {
    /// The input was empty (or only whitespace).
    Empty,
    /// A character that has no meaning in orbifold notation.
    UnexpectedChar(char),
    /// A minus sign: orders are positive.
    Negative,
    /// `(` without its `)`.
    Unclosed,
    /// `()` with nothing inside.
    EmptyParentheses,
    /// The text in parentheses is not a number, a fraction, a decimal or `inf`.
    NotANumber(String),
    /// An order of zero.
    Zero,
    /// A fraction with denominator zero.
    DivisionByZero,
    /// An order between 0 and 1 (a corner wider than π).
    BelowOne(String),
    /// A number too large to represent exactly.
    TooLarge,
    /// A non-integer order outside a kaleidoscopic signature.
    NonIntegerOutsideKaleidoscope(String),
    /// A handle `o` written after other items.
    HandleNotFirst,
    /// An order or mirror written after a cross-cap.
    AfterCrossCap(&'static str),
    /// Valid Conway notation, but not a kaleidoscopic signature `*k₁…k_N`.
    NotKaleidoscopic(String),
}

/// A signature that could not be read, with the position (1-based character column) and the reason.
///
/// ```
/// use orbifold::Signature;
/// let err = "*2q".parse::<Signature>().unwrap_err();
/// assert_eq!(err.position(), 3);
/// assert!(err.to_string().contains("position 3"));
/// ```
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ParseError {
    input: String,
    position: usize,
    width: usize,
    kind: ParseErrorKind,
}

impl ParseError {
    pub(crate) fn new(input: &str, position: usize, width: usize, kind: ParseErrorKind) -> Self {
        ParseError {
            input: input.to_string(),
            position,
            width: width.max(1),
            kind,
        }
    }

    /// The 1-based character column where the problem starts.
    pub fn position(&self) -> usize {
        self.position
    }

    /// What went wrong.
    pub fn kind(&self) -> &ParseErrorKind {
        &self.kind
    }

    /// The input, and under it a caret line marking the problem, for terminal output.
    pub fn snippet(&self) -> String {
        let shown: String = self
            .input
            .chars()
            .map(|c| if c.is_control() { ' ' } else { c })
            .collect();
        let pad = " ".repeat(self.position.saturating_sub(1));
        format!("  {shown}\n  {pad}{}", "^".repeat(self.width))
    }
}

impl fmt::Display for ParseError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "invalid signature {:?} at position {}: ",
            self.input, self.position
        )?;
        match &self.kind {
            ParseErrorKind::Empty => {
                f.write_str("the signature is empty; write at least `*` (the one-mirror hemisphere)")
            }
            ParseErrorKind::UnexpectedChar(c) => write!(
                f,
                "unexpected character {c:?}; expected an order (a digit 2-9, a number in parentheses such as (12) or (3/2), ∞ or inf), `*`, `×`/`x` or `o`"
            ),
            ParseErrorKind::Negative => f.write_str("orders cannot be negative; a corner of order k has angle π/k with k > 1"),
            ParseErrorKind::Unclosed => f.write_str("`(` is never closed; write orders of 10 or more as (12)"),
            ParseErrorKind::EmptyParentheses => f.write_str("`()` holds no order"),
            ParseErrorKind::NotANumber(text) => write!(
                f,
                "{text:?} is not an order; inside parentheses write an integer (12), a fraction (3/2), a decimal (1.5) or inf"
            ),
            ParseErrorKind::Zero => f.write_str("an order of 0 is meaningless; a corner of order k has angle π/k, so k must be at least 1"),
            ParseErrorKind::DivisionByZero => f.write_str("the fraction divides by zero"),
            ParseErrorKind::BelowOne(value) => write!(
                f,
                "order {value} is less than 1: the corner angle π/k would exceed π, so the polygon could not be convex"
            ),
            ParseErrorKind::TooLarge => f.write_str("the number is too large to represent exactly (at most 2^64 − 1, with at most 19 significant digits)"),
            ParseErrorKind::NonIntegerOutsideKaleidoscope(value) => write!(
                f,
                "order {value} is not an integer; non-integer orders are only meaningful for the corners of a kaleidoscopic room *k₁…k_N"
            ),
            ParseErrorKind::HandleNotFirst => f.write_str("a handle `o` must be written before every other item, as in `o` or `o*`"),
            ParseErrorKind::AfterCrossCap(what) => {
                write!(f, "{what} after a cross-cap `×`; Conway notation writes cross-caps last, as in `22×` or `*×`")
            }
            ParseErrorKind::NotKaleidoscopic(why) => write!(f, "not a kaleidoscopic signature *k₁…k_N: {why}"),
        }
    }
}

impl std::error::Error for ParseError {}

/// The items of a symbol as written, before any normalisation other than dropping orders of 1.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub(crate) struct RawSymbol {
    pub handles: u32,
    pub cones: Vec<Order>,
    pub boundaries: Vec<Vec<Order>>,
    pub crosscaps: u32,
    /// Position and text of the first non-integer order, checked once the whole symbol is known.
    pub first_non_integer: Option<(usize, usize, String)>,
}

impl RawSymbol {
    pub fn is_kaleidoscopic(&self) -> bool {
        self.handles == 0
            && self.crosscaps == 0
            && self.cones.is_empty()
            && self.boundaries.len() == 1
    }
}

/// Reads any Conway orbifold symbol, or a wallpaper group's short IUCr name (`p6`, `pgg`:
/// [`crate::groups::wallpaper_symbol`]). Non-integer orders are rejected unless the symbol is
/// kaleidoscopic.
pub(crate) fn parse_symbol(input: &str) -> Result<RawSymbol, ParseError> {
    if let Some(conway) = crate::groups::wallpaper_symbol(input.trim()) {
        return parse_symbol(conway);
    }
    let chars: Vec<char> = input.chars().collect();
    let mut reader = Reader {
        input,
        chars: &chars,
        at: 0,
        raw: RawSymbol::default(),
    };
    reader.run()?;
    let raw = reader.raw;
    if let Some((position, width, text)) = &raw.first_non_integer
        && !raw.is_kaleidoscopic()
    {
        return Err(ParseError::new(
            input,
            *position,
            *width,
            ParseErrorKind::NonIntegerOutsideKaleidoscope(text.clone()),
        ));
    }
    Ok(raw)
}

struct Reader<'a> {
    input: &'a str,
    chars: &'a [char],
    at: usize,
    raw: RawSymbol,
}

impl Reader<'_> {
    fn error(&self, at: usize, width: usize, kind: ParseErrorKind) -> ParseError {
        ParseError::new(self.input, at + 1, width, kind)
    }

    fn run(&mut self) -> Result<(), ParseError> {
        if self.chars.iter().all(|c| c.is_whitespace()) {
            return Err(self.error(self.chars.len(), 1, ParseErrorKind::Empty));
        }
        while self.at < self.chars.len() {
            let start = self.at;
            let c = self.chars[start];
            match c {
                c if c.is_whitespace() => self.at += 1,
                '*' => {
                    self.reject_after_crosscap(start, "a mirror `*`")?;
                    self.raw.boundaries.push(Vec::new());
                    self.at += 1;
                }
                '×' | 'x' | 'X' => {
                    self.raw.crosscaps += 1;
                    self.at += 1;
                }
                'o' | 'O' => {
                    if self.raw.crosscaps > 0
                        || !self.raw.cones.is_empty()
                        || !self.raw.boundaries.is_empty()
                    {
                        return Err(self.error(start, 1, ParseErrorKind::HandleNotFirst));
                    }
                    self.raw.handles += 1;
                    self.at += 1;
                }
                '-' | '−' => return Err(self.error(start, 1, ParseErrorKind::Negative)),
                _ => {
                    let order = self.order()?;
                    self.reject_after_crosscap(start, "an order")?;
                    self.push_order(order, start);
                }
            }
        }
        Ok(())
    }

    fn reject_after_crosscap(&self, at: usize, what: &'static str) -> Result<(), ParseError> {
        if self.raw.crosscaps > 0 {
            return Err(self.error(at, 1, ParseErrorKind::AfterCrossCap(what)));
        }
        Ok(())
    }

    fn push_order(&mut self, order: Order, start: usize) {
        if !order.is_orbifold_order() && self.raw.first_non_integer.is_none() {
            self.raw.first_non_integer = Some((start + 1, self.at - start, order.to_string()));
        }
        if order.is_one() {
            return;
        }
        match self.raw.boundaries.last_mut() {
            Some(boundary) => boundary.push(order),
            None => self.raw.cones.push(order),
        }
    }

    /// Reads one order at `self.at`: a digit, `∞`, `inf`, or a parenthesised number.
    fn order(&mut self) -> Result<Order, ParseError> {
        let start = self.at;
        let c = self.chars[start];
        if let Some(d) = c.to_digit(10) {
            self.at += 1;
            return match d {
                0 => Err(self.error(start, 1, ParseErrorKind::Zero)),
                d => Ok(Order::integer(u64::from(d))),
            };
        }
        if c == '∞' {
            self.at += 1;
            return Ok(Order::Infinite);
        }
        if self.starts_with_inf(start) {
            self.at += 3;
            return Ok(Order::Infinite);
        }
        if c == '(' {
            return self.parenthesised();
        }
        Err(self.error(start, 1, ParseErrorKind::UnexpectedChar(c)))
    }

    fn starts_with_inf(&self, at: usize) -> bool {
        let word: String = self.chars[at..].iter().take(3).collect();
        word.eq_ignore_ascii_case("inf")
    }

    fn parenthesised(&mut self) -> Result<Order, ParseError> {
        let open = self.at;
        let Some(close) = self.chars[open..]
            .iter()
            .position(|&c| c == ')')
            .map(|i| open + i)
        else {
            return Err(self.error(open, self.chars.len() - open, ParseErrorKind::Unclosed));
        };
        self.at = close + 1;
        let width = close + 1 - open;
        let text: String = self.chars[open + 1..close].iter().collect();
        let text = text.trim();
        let fail = |kind| Err(self.error(open, width, kind));
        if text.is_empty() {
            return fail(ParseErrorKind::EmptyParentheses);
        }
        if text == "∞" || text.eq_ignore_ascii_case("inf") || text.eq_ignore_ascii_case("infinity")
        {
            return Ok(Order::Infinite);
        }
        if text.starts_with('-') || text.starts_with('−') {
            return fail(ParseErrorKind::Negative);
        }
        let (numer, denom) = match parse_number(text) {
            Ok(pair) => pair,
            Err(kind) => return fail(kind),
        };
        if denom == 0 {
            return fail(ParseErrorKind::DivisionByZero);
        }
        if numer == 0 {
            return fail(ParseErrorKind::Zero);
        }
        if numer < denom {
            return fail(ParseErrorKind::BelowOne(text.to_string()));
        }
        Ok(Order::ratio(numer, denom).expect("denominator checked non-zero"))
    }
}

/// Parses `12`, `3/2` or `1.5` into numerator and denominator (not yet reduced).
fn parse_number(text: &str) -> Result<(u64, u64), ParseErrorKind> {
    let not_a_number = || ParseErrorKind::NotANumber(text.to_string());
    let integer = |s: &str| -> Result<u64, ParseErrorKind> {
        if s.is_empty() || !s.bytes().all(|b| b.is_ascii_digit()) {
            return Err(not_a_number());
        }
        s.parse::<u64>().map_err(|_| ParseErrorKind::TooLarge)
    };
    if let Some((p, q)) = text.split_once('/') {
        return Ok((integer(p.trim())?, integer(q.trim())?));
    }
    if let Some((whole, fraction)) = text.split_once('.') {
        let digits = format!("{whole}{fraction}");
        if whole.is_empty() && fraction.is_empty() {
            return Err(not_a_number());
        }
        let numer = integer(&digits)?;
        let denom = u32::try_from(fraction.len())
            .ok()
            .and_then(|n| 10u64.checked_pow(n))
            .ok_or(ParseErrorKind::TooLarge)?;
        return Ok((numer, denom));
    }
    Ok((integer(text)?, 1))
}
