//! The statement parser: tokens of one statement to a typed statement (patent Fig. 10A, the
//! keyword identification numbers of Table 1: definitions 1–9, cutting statements 11–15,
//! modifiers 111–120). It checks form only; names are resolved by the translator.

use super::lex::{Tok, Token};
use super::TranslateError;

pub use super::ast::*;

struct Parser<'a> {
    toks: &'a [Token],
    pos: usize,
    line: u32,
    end_col: u32,
}

/// Parses the tokens of one statement; `end_col` is the column just past its text.
pub fn parse(toks: &[Token], line: u32, end_col: u32) -> Result<Stmt, TranslateError> {
    let mut p = Parser {
        toks,
        pos: 0,
        line,
        end_col,
    };
    let stmt = p.statement()?;
    if let Some(t) = p.peek() {
        return Err(p.err_at(
            t.col,
            format!("{} after the end of the statement", t.tok.describe()),
        ));
    }
    Ok(stmt)
}

impl Parser<'_> {
    fn peek(&self) -> Option<&Token> {
        self.toks.get(self.pos)
    }

    fn peek_tok(&self) -> Option<&Tok> {
        self.peek().map(|t| &t.tok)
    }

    fn col(&self) -> u32 {
        self.peek().map_or(self.end_col, |t| t.col)
    }

    fn err_at(&self, col: u32, message: String) -> TranslateError {
        TranslateError {
            line: self.line,
            col,
            message,
        }
    }

    fn err_here(&self, wanted: &str) -> TranslateError {
        match self.peek() {
            Some(t) => self.err_at(
                t.col,
                format!("expected {wanted}, found {}", t.tok.describe()),
            ),
            None => self.err_at(
                self.end_col,
                format!("expected {wanted}, but the statement ends"),
            ),
        }
    }

    fn eat(&mut self, tok: &Tok) -> bool {
        if self.peek_tok() == Some(tok) {
            self.pos += 1;
            true
        } else {
            false
        }
    }

    fn expect(&mut self, tok: Tok, wanted: &str) -> Result<(), TranslateError> {
        if self.eat(&tok) {
            Ok(())
        } else {
            Err(self.err_here(wanted))
        }
    }

    /// A unit separator: `,` or `/`.
    fn sep(&mut self) -> bool {
        self.eat(&Tok::Comma) || self.eat(&Tok::Slash)
    }

    fn expect_sep(&mut self) -> Result<(), TranslateError> {
        if self.sep() {
            Ok(())
        } else {
            Err(self.err_here("',' or '/'"))
        }
    }

    fn word(&mut self) -> Option<(String, u32)> {
        match self.peek() {
            Some(Token {
                tok: Tok::Word(w),
                col,
            }) => {
                let r = (w.clone(), *col);
                self.pos += 1;
                Some(r)
            }
            _ => None,
        }
    }

    fn peek_word(&self) -> Option<&str> {
        match self.peek_tok() {
            Some(Tok::Word(w)) => Some(w.as_str()),
            _ => None,
        }
    }

    fn num(&mut self, what: &str) -> Result<(f64, u32), TranslateError> {
        match self.peek() {
            Some(Token {
                tok: Tok::Num(v),
                col,
            }) => {
                let r = (*v, *col);
                self.pos += 1;
                Ok(r)
            }
            _ => Err(self.err_here(what)),
        }
    }

    /// The number of a name after its keyword at `col`: a whole number from 1.
    fn name_number(&mut self, kw: &str, col: u32) -> Result<Name, TranslateError> {
        let (v, ncol) = self.num(&format!("the number of the {kw}"))?;
        if v.fract() != 0.0 || !(1.0..=999_999.0).contains(&v) {
            return Err(self.err_at(
                ncol,
                format!("{kw} numbers are whole numbers from 1, not {v}"),
            ));
        }
        Ok(Name { n: v as u32, col })
    }

    /// A name with the given keyword, e.g. `P3`.
    fn named(&mut self, kw: &str, what: &str) -> Result<Name, TranslateError> {
        match self.peek_word() {
            Some(w) if w == kw => {
                let (_, col) = self.word().unwrap_or_default();
                self.name_number(kw, col)
            }
            _ => Err(self.err_here(what)),
        }
    }

    /// `(a, b[, c])` with `min` to 3 numbers; missing ones are 0.
    fn coords(&mut self, min: usize) -> Result<[f64; 3], TranslateError> {
        self.expect(Tok::LParen, "'(' and coordinates")?;
        let mut v = [0.0; 3];
        let mut k = 0;
        loop {
            if k == 3 {
                return Err(self.err_here("')' after at most 3 coordinates"));
            }
            v[k] = self.num("a coordinate")?.0;
            k += 1;
            if self.eat(&Tok::RParen) {
                break;
            }
            self.expect(Tok::Comma, "',' or ')'")?;
        }
        if k < min {
            return Err(self.err_at(
                self.toks[self.pos - 1].col,
                format!("{min} coordinates are needed here, {k} given"),
            ));
        }
        Ok(v)
    }

    fn statement(&mut self) -> Result<Stmt, TranslateError> {
        let Some((kw, col)) = self.word() else {
            return Err(self.err_here(
                "a keyword (P, DA, L, C, PAT, MAC, GO, GD, CL, DRL, TAP, REM, MIL, BOR)",
            ));
        };
        match kw.as_str() {
            "P" | "DA" | "L" | "C" | "PAT" | "MAC" => {
                let name = self.name_number(&kw, col)?;
                self.expect(Tok::Eq, "'=' after the name")?;
                self.definition(&kw, name)
            }
            "GO" => {
                self.sep();
                let da = if self.peek_word() == Some("DA") {
                    let d = self.named("DA", "DA")?;
                    self.expect_sep()?;
                    Some(d)
                } else {
                    None
                };
                let v = self.three_numbers()?;
                Ok(Stmt::Go { da, v })
            }
            "GD" => {
                self.sep();
                Ok(Stmt::Gd {
                    v: self.three_numbers()?,
                })
            }
            "CL" => Ok(Stmt::Cl),
            "DRL" => self.cut(CycleKind::Drl),
            "TAP" => self.cut(CycleKind::Tap),
            "REM" => self.cut(CycleKind::Rem),
            "MIL" => self.cut(CycleKind::Mil),
            "BOR" => self.cut(CycleKind::Bor),
            _ => Err(self.err_at(col, format!("'{kw}' is not a statement keyword"))),
        }
    }

    fn three_numbers(&mut self) -> Result<[f64; 3], TranslateError> {
        let mut v = [0.0; 3];
        for (i, x) in v.iter_mut().enumerate() {
            if i > 0 {
                self.expect_sep()?;
            }
            *x = self.num(["x", "y", "z"][i])?.0;
        }
        Ok(v)
    }

    fn definition(&mut self, kw: &str, name: Name) -> Result<Stmt, TranslateError> {
        match kw {
            "DA" => {
                if self.peek_word() == Some("DA") {
                    let base = self.named("DA", "DA")?;
                    self.expect_sep()?;
                    let v = self.coords(3)?;
                    Ok(Stmt::Da {
                        name,
                        base: Some(base),
                        v,
                    })
                } else {
                    let v = self.coords(3)?;
                    Ok(Stmt::Da {
                        name,
                        base: None,
                        v,
                    })
                }
            }
            "P" => Ok(Stmt::Point {
                name,
                expr: self.point_expr()?,
            }),
            "L" => {
                let a = self.named("P", "a point Pn")?;
                self.expect_sep()?;
                let by = match self.peek_word() {
                    Some("A") => {
                        self.pos += 1;
                        LineBy::Angle(self.num("an angle in degrees after A")?.0)
                    }
                    _ => LineBy::Point(self.named("P", "a second point Pn or an angle A")?),
                };
                Ok(Stmt::Line { name, a, by })
            }
            "C" => {
                let c = self.named("P", "a point Pn")?;
                self.expect_sep()?;
                let by = match self.peek_word() {
                    Some("R") => {
                        let col = self.col();
                        self.pos += 1;
                        CircleBy::Radius(self.num("a radius after R")?.0, col)
                    }
                    _ => {
                        let b = self.named("P", "a radius R or a second point Pn")?;
                        self.expect_sep()?;
                        let c3 = self.named("P", "a third point Pn")?;
                        CircleBy::Through(b, c3)
                    }
                };
                Ok(Stmt::Circle { name, c, by })
            }
            "PAT" => self.pattern(name),
            _ => {
                let items = self.designations()?;
                Ok(Stmt::Mac { name, items })
            }
        }
    }

    fn pattern(&mut self, name: Name) -> Result<Stmt, TranslateError> {
        let (mut da, mut nh, mut centre, mut r, mut sa, mut ia) =
            (None, None, None, None, None, None);
        loop {
            let Some((w, col)) = self.word() else {
                return Err(self.err_here("DA, NH, P, R, SA or IA"));
            };
            let dup = match w.as_str() {
                "DA" => da.replace(self.name_number("DA", col)?).is_some(),
                "P" => centre.replace(self.name_number("P", col)?).is_some(),
                "NH" => nh
                    .replace((self.num("a hole count after NH")?.0, col))
                    .is_some(),
                "R" => r.replace((self.num("a radius after R")?.0, col)).is_some(),
                "SA" => sa.replace(self.num("an angle after SA")?.0).is_some(),
                "IA" => ia
                    .replace((self.num("an angle after IA")?.0, col))
                    .is_some(),
                _ => {
                    return Err(self.err_at(
                        col,
                        format!("'{w}' has no place in a pattern (DA, NH, P, R, SA, IA)"),
                    ))
                }
            };
            if dup {
                return Err(self.err_at(col, format!("{w} is given twice")));
            }
            if self.peek().is_none() {
                break;
            }
            self.expect_sep()?;
        }
        let missing = |what: &str| self.err_at(self.end_col, format!("the pattern needs {what}"));
        Ok(Stmt::Pat {
            name,
            da,
            nh: nh.ok_or_else(|| missing("a hole count NH"))?,
            centre: centre.ok_or_else(|| missing("a centre point P"))?,
            r: r.ok_or_else(|| missing("a radius R"))?,
            sa: sa.unwrap_or(0.0),
            ia,
        })
    }

    fn selector(&mut self) -> Result<Sel, TranslateError> {
        self.expect_sep()?;
        let sel = match self.peek_word() {
            Some("XL") => Sel::Xl,
            Some("XS") => Sel::Xs,
            Some("YL") => Sel::Yl,
            Some("YS") => Sel::Ys,
            _ => return Err(self.err_here("a selector XL, XS, YL or YS")),
        };
        self.pos += 1;
        Ok(sel)
    }

    fn point_expr(&mut self) -> Result<PointExpr, TranslateError> {
        match self.peek_word() {
            None => Ok(PointExpr::Coords(self.coords(2)?)),
            Some("P") => {
                let base = self.named("P", "P")?;
                let d = self.coords(2)?;
                Ok(PointExpr::Rel { base, d })
            }
            Some("L") => {
                let a = self.named("L", "L")?;
                self.expect_sep()?;
                match self.peek_word() {
                    Some("L") => {
                        let b = self.named("L", "L")?;
                        Ok(PointExpr::LineLine { a, b })
                    }
                    Some("C") => {
                        let c = self.named("C", "C")?;
                        let sel = self.selector()?;
                        Ok(PointExpr::LineCircle { l: a, c, sel })
                    }
                    _ => Err(self.err_here("a line Ln or a circle Cn")),
                }
            }
            Some("C") => {
                let a = self.named("C", "C")?;
                self.expect_sep()?;
                match self.peek_word() {
                    Some("L") => {
                        let l = self.named("L", "L")?;
                        let sel = self.selector()?;
                        Ok(PointExpr::LineCircle { l, c: a, sel })
                    }
                    Some("C") => {
                        let b = self.named("C", "C")?;
                        let sel = self.selector()?;
                        Ok(PointExpr::CircleCircle { a, b, sel })
                    }
                    _ => Err(self.err_here("a line Ln or a circle Cn")),
                }
            }
            Some(_) => Err(self.err_here("coordinates (x, y[, z]), Pm(dx, dy[, dz]), La, Lb or an intersection with a circle")),
        }
    }

    fn designation(&mut self) -> Result<Desig, TranslateError> {
        if self.peek_tok() == Some(&Tok::LParen) {
            let col = self.col();
            self.pos += 1;
            let expr = if matches!(self.peek_tok(), Some(Tok::Num(_))) {
                self.pos -= 1;
                PointExpr::Coords(self.coords(2)?)
            } else {
                let e = self.point_expr()?;
                let name = if self.eat(&Tok::Eq) {
                    Some(self.named("P", "a point name Pn after '='")?)
                } else {
                    None
                };
                self.expect(Tok::RParen, "')'")?;
                return Ok(Desig::Inline { expr: e, name, col });
            };
            return Ok(Desig::Inline {
                expr,
                name: None,
                col,
            });
        }
        let Some((w, col)) = self.word() else {
            return Err(self.err_here("a designation (DA, P, PAT, MAC, C or an inline point)"));
        };
        let name = self.name_number(&w, col);
        match w.as_str() {
            "DA" => Ok(Desig::Da(name?)),
            "P" => Ok(Desig::Point(name?)),
            "PAT" => Ok(Desig::Pat(name?)),
            "MAC" => Ok(Desig::Mac(name?)),
            "C" => Ok(Desig::Circle(name?)),
            _ => Err(self.err_at(
                col,
                format!("'{w}' is not a designation (DA, P, PAT, MAC, C or an inline point)"),
            )),
        }
    }

    fn designations(&mut self) -> Result<Vec<Desig>, TranslateError> {
        let mut v = vec![self.designation()?];
        while self.peek().is_some() {
            self.expect_sep()?;
            v.push(self.designation()?);
        }
        Ok(v)
    }

    fn cut(&mut self, kind: CycleKind) -> Result<Stmt, TranslateError> {
        self.sep();
        let (t, tcol) = self.num("a tool number")?;
        if t.fract() != 0.0 || !(1.0..=99_999.0).contains(&t) {
            return Err(self.err_at(tcol, format!("tool number {t} is not 1 to 5 digits")));
        }
        let mut mods = Mods::default();
        let mut desigs = Vec::new();
        while self.peek().is_some() {
            self.expect_sep()?;
            let col = self.col();
            let w = self.peek_word().map(str::to_string);
            let slot: Option<&mut Valued> = match w.as_deref() {
                Some("DP") => Some(&mut mods.dp),
                Some("DI") => Some(&mut mods.di),
                Some("FR") => Some(&mut mods.fr),
                Some("SS") => Some(&mut mods.ss),
                Some("SCL") => Some(&mut mods.scl),
                Some("DW") => Some(&mut mods.dw),
                Some("DH") => Some(&mut mods.dh),
                _ => None,
            };
            let w = w.unwrap_or_default();
            let dup = if let Some(slot) = slot {
                self.pos += 1;
                let v = match self.peek_tok() {
                    Some(Tok::Num(v)) => *v,
                    _ => return Err(self.err_here(&format!("a value after {w}"))),
                };
                self.pos += 1;
                slot.replace((v, col)).is_some()
            } else {
                match w.as_str() {
                    "RGT" => {
                        self.pos += 1;
                        mods.rgt.replace(col).is_some()
                    }
                    "LFT" => {
                        self.pos += 1;
                        mods.lft.replace(col).is_some()
                    }
                    "SDP" => {
                        self.pos += 1;
                        let v = match self.peek_tok() {
                            Some(Tok::Num(v)) => {
                                let v = *v;
                                self.pos += 1;
                                Some(v)
                            }
                            _ => None,
                        };
                        mods.sdp.replace((v, col)).is_some()
                    }
                    _ => {
                        desigs.push(self.designation()?);
                        false
                    }
                }
            };
            if dup {
                return Err(self.err_at(col, format!("{w} is given twice")));
            }
        }
        Ok(Stmt::Cut(Cut {
            kind,
            tool: (t as u32, tcol),
            mods,
            desigs,
        }))
    }
}

#[cfg(test)]
mod tests {
    use super::super::lex::scan;
    use super::*;

    fn p(s: &str) -> Result<Stmt, TranslateError> {
        let mut t = Vec::new();
        scan(s, 1, &mut t)?;
        parse(&t, 1, s.chars().count() as u32 + 1)
    }

    #[test]
    fn parses_the_table_b_statements() {
        assert_eq!(
            p("DA1 = (200, 0, -450)").unwrap(),
            Stmt::Da {
                name: Name { n: 1, col: 1 },
                base: None,
                v: [200.0, 0.0, -450.0]
            }
        );
        let Stmt::Cut(c) = p("BOR, 610/DP35, SDP/DA1, P1").unwrap() else {
            panic!("not a cut")
        };
        assert_eq!(c.kind, CycleKind::Bor);
        assert_eq!(c.tool, (610, 6));
        assert_eq!(c.mods.dp, Some((35.0, 10)));
        assert_eq!(c.mods.sdp, Some((None, 16)));
        assert_eq!(c.desigs.len(), 2);
        let Stmt::Cut(c) = p("DRL, 105/DP15/DA1, P2, (P2(0,30)=P3), (P3(0,170)=P4)").unwrap()
        else {
            panic!("not a cut")
        };
        assert_eq!(
            c.desigs[2],
            Desig::Inline {
                expr: PointExpr::Rel {
                    base: Name { n: 2, col: 25 },
                    d: [0.0, 30.0, 0.0]
                },
                name: Some(Name { n: 3, col: 34 }),
                col: 24
            }
        );
        assert!(matches!(
            p("PAT1 = DA1, NH6, P1, R65, SA30, IA60").unwrap(),
            Stmt::Pat { nh: (6.0, _), .. }
        ));
        assert!(matches!(
            p("P5 = L1, C2, YS").unwrap(),
            Stmt::Point {
                expr: PointExpr::LineCircle { sel: Sel::Ys, .. },
                ..
            }
        ));
        assert!(matches!(
            p("GO, DA1, 0, 0, 10").unwrap(),
            Stmt::Go { da: Some(_), .. }
        ));
    }

    #[test]
    fn syntax_errors_point_at_the_column() {
        let e = p("DRL, 106/DP20/PAT").unwrap_err();
        assert_eq!(e.col, 18);
        let e = p("P1 = (1)").unwrap_err();
        assert!(e.message.contains("2 coordinates"), "{e}");
        let e = p("XYZ1 = (1, 2)").unwrap_err();
        assert_eq!(e.col, 1);
        let e = p("DRL, 106/DP20, DP30/P1").unwrap_err();
        assert_eq!((e.col, e.message.as_str()), (16, "DP is given twice"));
        let e = p("P1 = (1, 2) 3").unwrap_err();
        assert_eq!(e.col, 13);
        let e = p("P1.5 = (1, 2)").unwrap_err();
        assert_eq!(e.col, 2);
        assert!(p("DRL, 106.5/DP3/P1").is_err());
        assert!(p("P3 = L1, C2").is_err());
    }
}
