//! ABB RAPID reader, for modules exported by Grasshopper (HAL, Robots, Taco) and RobotStudio.
//!
//! Read: `MODULE … ENDMODULE`, `PROC … ENDPROC`; declarations `CONST`/`PERS`/`VAR` of
//! `robtarget` (`[[x,y,z],[q1,q2,q3,q4],[cf1,cf4,cf6,cfx],[eax…]]`, mm; the orientation,
//! configuration and external axes are dropped), `speeddata` (`[v_tcp, v_ori, v_leax, v_reax]`,
//! only `v_tcp` mm/s is used), `zonedata` (`[finep, pzone_tcp, …]`, only `finep` and
//! `pzone_tcp` mm are used); instructions `MoveL`, `MoveJ`, `MoveC` with named or inline
//! robtargets and `Offs(p, dx, dy, dz)` (mm), `\V:=` (mm/s) and `\Z:=` (mm) overrides, `\Inpos`
//! (= fine). Comments start with `!`. Keywords are case-insensitive, as in RAPID.
//!
//! Predefined speeddata `v5 … v7000` are the TCP speed in mm/s given by the name; `vmax` is
//! taken as 7000 mm/s (ABB: "the robot's maximum", robot-dependent — a warning says so).
//! Predefined zonedata `z0 … z200` have `pzone_tcp` = the number in mm, except `z0` = 0.3 mm
//! (ABB's table); `fine` stops exactly.
//!
//! Extrusion: `MoveL` and `MoveC` print, `MoveJ` travels. `SetDO`/`SetAO` and all other
//! instructions are skipped and listed in one warning.
//!
//! Execution, as the controller runs the module: from `PROC main` (or the procedure named by
//! [`ReadOptions::proc`]), following its procedure calls (`name;` statements naming a `PROC`
//! of the module) in order, up to [`MAX_CALL_DEPTH`] deep; a recursive call is an error naming
//! the chain. `FOR`/`WHILE` bodies are read once (a warning says so). An `IF`/`TEST` whose
//! branches reach the same moves is read through its first branch; one whose branches reach
//! different procedures or moves (a choice made at run time, e.g. on a digital input) is an
//! error listing the procedures and where they are called, unless the entry procedure is
//! named. A module without `main` is read whole in file order (control flow not executed) when
//! at most one procedure has moves, and refused listing its procedures otherwise. `ERROR`,
//! `UNDO` and `BACKWARD` handlers are not run.
//!
//! Frames: the part frame is the work object the print moves (`MoveL`, `MoveC`) use most.
//! Targets in another declared `wobjdata` are put in it through both work objects' uframe and
//! oframe; moves in `wobj0` while the print uses another work object (a home position) are
//! not part points: they are skipped with a warning naming their lines. A `tooldata` whose
//! tool frame is not the identity is noted in the warnings; the robot's nozzle model is kept.
//! Declarations may appear anywhere in the file. The first move sets the start point.
//! `MoveAbsJ` (joint targets) is skipped with a warning.

use std::collections::{BTreeSet, HashMap};

use super::{circle_through, perr, Move, MoveKind, Procedure, ReadOptions, Toolpath, Zone};
use crate::error::{Error, Result};
use crate::math::{Frame, M3, V3};

const M_PER_MM: f64 = 1e-3;
/// TCP speed assumed for `vmax`, mm/s.
const VMAX_MM_S: f64 = 7000.0;
const SPEEDS_MM_S: [u32; 25] = [
    5, 10, 20, 30, 40, 50, 60, 80, 100, 150, 200, 300, 400, 500, 600, 800, 1000, 1500, 2000, 2500,
    3000, 4000, 5000, 6000, 7000,
];
const ZONES_MM: [u32; 13] = [1, 5, 10, 15, 20, 30, 40, 50, 60, 80, 100, 150, 200];

#[derive(Clone, Debug, PartialEq)]
enum Tok {
    Ident(String),
    Num(f64),
    Str,
    Punct(String),
    Eof,
}

#[derive(Clone, Debug)]
struct Token {
    tok: Tok,
    line: usize,
    col: usize,
}

fn describe(t: &Tok) -> String {
    match t {
        Tok::Ident(s) => format!("'{s}'"),
        Tok::Num(v) => format!("'{v}'"),
        Tok::Str => "a string".into(),
        Tok::Punct(p) => format!("'{p}'"),
        Tok::Eof => "end of file".into(),
    }
}

/// Where the number starting at `i` ends: digits and points, then an exponent when one
/// with digits follows.
fn number_end(ch: &[char], i: usize) -> usize {
    let mut j = i;
    while j < ch.len() && (ch[j].is_ascii_digit() || ch[j] == '.') {
        j += 1;
    }
    if j < ch.len() && (ch[j] == 'e' || ch[j] == 'E') {
        let mut k = j + 1;
        if k < ch.len() && (ch[k] == '+' || ch[k] == '-') {
            k += 1;
        }
        if k < ch.len() && ch[k].is_ascii_digit() {
            while k < ch.len() && ch[k].is_ascii_digit() {
                k += 1;
            }
            j = k;
        }
    }
    j
}

fn lex(file: &str, text: &str) -> Result<Vec<Token>> {
    let mut out = Vec::new();
    let mut last_line = 1;
    for (li, line) in text.lines().enumerate() {
        let lineno = li + 1;
        last_line = lineno + 1;
        let ch: Vec<char> = line.chars().collect();
        let mut i = 0;
        while i < ch.len() {
            let c = ch[i];
            let col = i + 1;
            let mut push = |tok| {
                out.push(Token {
                    tok,
                    line: lineno,
                    col,
                })
            };
            if c.is_whitespace() {
                i += 1;
            } else if c == '!' {
                break;
            } else if c == '"' {
                match ch[i + 1..].iter().position(|&x| x == '"') {
                    Some(p) => {
                        push(Tok::Str);
                        i += p + 2;
                    }
                    None => {
                        return Err(perr(
                            file,
                            lineno,
                            ch.len() + 1,
                            format!("expected '\"' to close the string opened at column {col}"),
                        ))
                    }
                }
            } else if c.is_ascii_alphabetic() || c == '_' {
                let mut j = i;
                while j < ch.len() && (ch[j].is_ascii_alphanumeric() || ch[j] == '_') {
                    j += 1;
                }
                push(Tok::Ident(ch[i..j].iter().collect()));
                i = j;
            } else if c.is_ascii_digit()
                || (c == '.' && ch.get(i + 1).is_some_and(|d| d.is_ascii_digit()))
            {
                let j = number_end(&ch, i);
                let s: String = ch[i..j].iter().collect();
                match s.parse::<f64>() {
                    Ok(v) if v.is_finite() => push(Tok::Num(v)),
                    _ => {
                        return Err(perr(
                            file,
                            lineno,
                            col,
                            format!("expected a finite number, found '{s}'"),
                        ))
                    }
                }
                i = j;
            } else if c == ':' && ch.get(i + 1) == Some(&'=') {
                push(Tok::Punct(":=".into()));
                i += 2;
            } else {
                push(Tok::Punct(c.to_string()));
                i += 1;
            }
        }
    }
    out.push(Token {
        tok: Tok::Eof,
        line: last_line.max(1),
        col: 1,
    });
    Ok(out)
}

#[derive(Clone, Debug)]
enum Value {
    Num(f64),
    Bool(bool),
    Str,
    Ident(String, usize, usize),
    Agg(Vec<Value>, usize, usize),
    Call(String, Vec<Value>, usize, usize),
}

struct Arg {
    value: Value,
}

struct MoveStmt {
    instr: String,
    line: usize,
    col: usize,
    args: Vec<Arg>,
    opts: HashMap<String, Option<Value>>,
    end_line: usize,
    end_col: usize,
}

struct Parser<'a> {
    file: &'a str,
    toks: Vec<Token>,
    i: usize,
}

impl Parser<'_> {
    fn peek(&self) -> &Token {
        &self.toks[self.i.min(self.toks.len() - 1)]
    }
    fn next(&mut self) -> Token {
        let t = self.peek().clone();
        if self.i < self.toks.len() - 1 {
            self.i += 1;
        }
        t
    }
    fn is_punct(&self, p: &str) -> bool {
        matches!(&self.peek().tok, Tok::Punct(q) if q == p)
    }
    fn err_here(&self, expected: &str) -> Error {
        let t = self.peek();
        perr(
            self.file,
            t.line,
            t.col,
            format!("expected {expected}, found {}", describe(&t.tok)),
        )
    }
    fn expect(&mut self, p: &str, what: &str) -> Result<()> {
        if self.is_punct(p) {
            self.next();
            Ok(())
        } else {
            Err(self.err_here(what))
        }
    }
    fn skip_statement(&mut self) {
        while !matches!(self.peek().tok, Tok::Eof) && !self.is_punct(";") {
            self.next();
        }
        self.next();
    }
    fn skip_line(&mut self, line: usize) {
        while !matches!(self.peek().tok, Tok::Eof) && self.peek().line == line {
            self.next();
        }
    }
    fn ident(&mut self, what: &str) -> Result<(String, usize, usize)> {
        match self.peek().tok.clone() {
            Tok::Ident(s) => {
                let t = self.next();
                Ok((s, t.line, t.col))
            }
            _ => Err(self.err_here(what)),
        }
    }

    fn value(&mut self, depth: usize) -> Result<Value> {
        if depth > 64 {
            return Err(self.err_here("an aggregate nested less than 64 deep"));
        }
        let t = self.peek().clone();
        match t.tok {
            Tok::Num(v) => {
                self.next();
                Ok(Value::Num(v))
            }
            Tok::Str => {
                self.next();
                Ok(Value::Str)
            }
            Tok::Punct(ref p) if p == "-" || p == "+" => {
                self.next();
                match self.value(depth + 1)? {
                    Value::Num(v) => Ok(Value::Num(if p == "-" { -v } else { v })),
                    _ => Err(perr(
                        self.file,
                        t.line,
                        t.col + 1,
                        "expected a number after the sign",
                    )),
                }
            }
            Tok::Punct(ref p) if p == "[" => {
                self.next();
                let mut items = Vec::new();
                if self.is_punct("]") {
                    self.next();
                    return Ok(Value::Agg(items, t.line, t.col));
                }
                loop {
                    items.push(self.value(depth + 1)?);
                    if self.is_punct(",") {
                        self.next();
                    } else if self.is_punct("]") {
                        self.next();
                        return Ok(Value::Agg(items, t.line, t.col));
                    } else {
                        return Err(self.err_here(&format!(
                            "',' or ']' in the aggregate opened at line {} column {}",
                            t.line, t.col
                        )));
                    }
                }
            }
            Tok::Ident(ref s) => {
                self.next();
                match s.to_ascii_lowercase().as_str() {
                    "true" => return Ok(Value::Bool(true)),
                    "false" => return Ok(Value::Bool(false)),
                    _ => {}
                }
                if self.is_punct("(") {
                    self.next();
                    let mut args = Vec::new();
                    if !self.is_punct(")") {
                        loop {
                            args.push(self.value(depth + 1)?);
                            if self.is_punct(",") {
                                self.next();
                            } else {
                                break;
                            }
                        }
                    }
                    self.expect(")", &format!("',' or ')' in the call of {s}"))?;
                    return Ok(Value::Call(s.clone(), args, t.line, t.col));
                }
                Ok(Value::Ident(s.clone(), t.line, t.col))
            }
            _ => Err(self.err_here("a value (number, name or [aggregate])")),
        }
    }

    /// `\Name` or `\Name:=value` switches.
    fn switches(&mut self, opts: &mut HashMap<String, Option<Value>>) -> Result<()> {
        while self.is_punct("\\") {
            self.next();
            let (name, _, _) = self.ident("an optional argument name after '\\'")?;
            let v = if self.is_punct(":=") {
                self.next();
                Some(self.value(0)?)
            } else {
                None
            };
            opts.insert(name.to_ascii_lowercase(), v);
        }
        Ok(())
    }

    fn move_stmt(&mut self, instr: String, line: usize, col: usize) -> Result<MoveStmt> {
        let mut args = Vec::new();
        let mut opts = HashMap::new();
        loop {
            self.switches(&mut opts)?;
            let value = self.value(0)?;
            self.switches(&mut opts)?;
            args.push(Arg { value });
            if self.is_punct(",") {
                self.next();
            } else if self.is_punct(";") {
                let t = self.next();
                return Ok(MoveStmt {
                    instr,
                    line,
                    col,
                    args,
                    opts,
                    end_line: t.line,
                    end_col: t.col,
                });
            } else {
                return Err(self.err_here(&format!("',' or ';' in the arguments of {instr}")));
            }
        }
    }
}

fn num_of(v: &Value) -> Option<f64> {
    match v {
        Value::Num(x) => Some(*x),
        _ => None,
    }
}

fn pos_of(v: &Value) -> Option<V3> {
    match v {
        Value::Agg(items, _, _) => match items.first() {
            Some(Value::Agg(p, _, _)) if p.len() == 3 => {
                Some(V3::new(num_of(&p[0])?, num_of(&p[1])?, num_of(&p[2])?))
            }
            _ => None,
        },
        _ => None,
    }
}

fn loc(v: &Value) -> (usize, usize) {
    match v {
        Value::Ident(_, l, c) | Value::Agg(_, l, c) | Value::Call(_, _, l, c) => (*l, *c),
        _ => (0, 0),
    }
}

struct Data {
    robtargets: HashMap<String, V3>,
    speeds: HashMap<String, f64>,
    zones: HashMap<String, Zone>,
}

fn robtarget(file: &str, data: &Data, v: &Value, at: (usize, usize)) -> Result<V3> {
    let (l, c) = if loc(v).0 == 0 { at } else { loc(v) };
    match v {
        Value::Ident(name, _, _) => data
            .robtargets
            .get(&name.to_ascii_lowercase())
            .copied()
            .ok_or_else(|| {
                perr(
                    file,
                    l,
                    c,
                    format!("undefined robtarget '{name}': expected a robtarget declared in the module"),
                )
            }),
        Value::Call(f, args, _, _) if f.eq_ignore_ascii_case("offs") && args.len() == 4 => {
            let base = robtarget(file, data, &args[0], (l, c))?;
            let d = [num_of(&args[1]), num_of(&args[2]), num_of(&args[3])];
            match d {
                [Some(x), Some(y), Some(z)] => Ok(base + V3::new(x, y, z) * M_PER_MM),
                _ => Err(perr(file, l, c, "expected Offs(robtarget, dx, dy, dz) with numbers")),
            }
        }
        _ => pos_of(v).map(|p| p * M_PER_MM).ok_or_else(|| {
            perr(
                file,
                l,
                c,
                "expected a robtarget name, Offs(…) or [[x,y,z],[q1,q2,q3,q4],[cf1,cf4,cf6,cfx],[eax…]]",
            )
        }),
    }
}

fn speed_of(file: &str, data: &Data, v: &Value, at: (usize, usize)) -> Result<f64> {
    let (l, c) = if loc(v).0 == 0 { at } else { loc(v) };
    let mm_s = match v {
        Value::Ident(name, _, _) => {
            let n = name.to_ascii_lowercase();
            if let Some(s) = data.speeds.get(&n) {
                *s
            } else if n == "vmax" {
                VMAX_MM_S
            } else if let Some(s) = n
                .strip_prefix('v')
                .and_then(|d| d.parse::<u32>().ok())
                .filter(|d| SPEEDS_MM_S.contains(d))
            {
                f64::from(s)
            } else {
                return Err(perr(
                    file,
                    l,
                    c,
                    format!(
                        "undefined speeddata '{name}': expected v5 … v7000, vmax or a speeddata \
                         declared in the module"
                    ),
                ));
            }
        }
        Value::Agg(items, _, _) => match items.first().and_then(num_of) {
            Some(s) => s,
            None => {
                return Err(perr(
                    file,
                    l,
                    c,
                    "expected speeddata [v_tcp, v_ori, v_leax, v_reax]",
                ))
            }
        },
        _ => {
            return Err(perr(
                file,
                l,
                c,
                "expected a speeddata name or [v_tcp, v_ori, v_leax, v_reax]",
            ))
        }
    };
    if mm_s.is_nan() || mm_s <= 0.0 {
        return Err(perr(
            file,
            l,
            c,
            format!("expected a positive TCP speed, found {mm_s} mm/s"),
        ));
    }
    Ok(mm_s * M_PER_MM)
}

fn zone_of(file: &str, data: &Data, v: &Value, at: (usize, usize)) -> Result<Zone> {
    let (l, c) = if loc(v).0 == 0 { at } else { loc(v) };
    match v {
        Value::Ident(name, _, _) => {
            let n = name.to_ascii_lowercase();
            if let Some(z) = data.zones.get(&n) {
                return Ok(*z);
            }
            if n == "fine" {
                return Ok(Zone::Fine);
            }
            if n == "z0" {
                return Ok(Zone::Blend(0.3 * M_PER_MM));
            }
            match n
                .strip_prefix('z')
                .and_then(|d| d.parse::<u32>().ok())
                .filter(|d| ZONES_MM.contains(d))
            {
                Some(z) => Ok(Zone::Blend(f64::from(z) * M_PER_MM)),
                None => Err(perr(
                    file,
                    l,
                    c,
                    format!(
                        "undefined zonedata '{name}': expected fine, z0 … z200 or a zonedata \
                         declared in the module"
                    ),
                )),
            }
        }
        Value::Agg(items, _, _) => {
            let finep = matches!(items.first(), Some(Value::Bool(true)));
            match (items.first(), items.get(1).and_then(num_of)) {
                (Some(Value::Bool(_)), Some(r)) if r >= 0.0 => Ok(if finep {
                    Zone::Fine
                } else {
                    Zone::Blend(r * M_PER_MM)
                }),
                _ => Err(perr(
                    file,
                    l,
                    c,
                    "expected zonedata [finep, pzone_tcp, pzone_ori, pzone_eax, zone_ori, \
                     zone_leax, zone_reax]",
                )),
            }
        }
        _ => Err(perr(
            file,
            l,
            c,
            "expected a zonedata name or [finep, pzone_tcp, …]",
        )),
    }
}

/// Deepest chain of procedure calls followed from the entry procedure.
pub const MAX_CALL_DEPTH: usize = 32;

/// One statement of a routine, as far as the reader needs it.
enum Stmt {
    Move(MoveStmt),
    /// An instruction named by an identifier: a procedure call when it names a PROC of the
    /// module, another instruction otherwise.
    Word {
        name: String,
        line: usize,
        col: usize,
    },
    /// `IF … ELSEIF … ELSE … ENDIF` or `TEST … CASE … DEFAULT … ENDTEST`; `complete` when an
    /// `ELSE`/`DEFAULT` arm exists.
    Branch {
        kind: &'static str,
        line: usize,
        col: usize,
        arms: Vec<Vec<Stmt>>,
        complete: bool,
    },
    /// `FOR … ENDFOR` or `WHILE … ENDWHILE`.
    Loop {
        kind: &'static str,
        line: usize,
        body: Vec<Stmt>,
    },
}

/// A `PROC` (or `FUNC`/`TRAP`) of the module.
struct Routine {
    name: String,
    line: usize,
    body: Vec<Stmt>,
}

type Decl = (String, String, Value, usize, usize);

/// A module as read: declarations, routines, statements outside any routine.
struct Module {
    decls: Vec<Decl>,
    routines: Vec<Routine>,
    top: Vec<Stmt>,
    notes: Vec<String>,
}

fn count_moves(body: &[Stmt]) -> usize {
    body.iter()
        .map(|s| match s {
            Stmt::Move(_) => 1,
            Stmt::Branch { arms, .. } => arms.iter().map(|a| count_moves(a)).sum(),
            Stmt::Loop { body, .. } => count_moves(body),
            Stmt::Word { .. } => 0,
        })
        .sum()
}

impl Parser<'_> {
    /// Skip tokens up to and including the identifier `word` (e.g. `THEN`, `DO`); an error
    /// naming `what` when a `;` or the end of the file comes first.
    fn skip_to_word(&mut self, word: &str, what: &str) -> Result<()> {
        loop {
            match &self.peek().tok {
                Tok::Ident(w) if w.eq_ignore_ascii_case(word) => {
                    self.next();
                    return Ok(());
                }
                Tok::Eof => return Err(self.err_here(what)),
                Tok::Punct(p) if p == ";" => return Err(self.err_here(what)),
                _ => {
                    self.next();
                }
            }
        }
    }

    /// A declaration after `CONST`/`PERS`/`VAR` (the keyword not yet consumed).
    fn decl(&mut self, m: &mut Module) -> Result<()> {
        self.next();
        let (ty, _, _) = self.ident("a data type after CONST/PERS/VAR")?;
        let (name, nl, nc) = self.ident("a data name")?;
        let tyl = ty.to_ascii_lowercase();
        if self.is_punct("{") {
            m.notes.push(format!(
                "{}:{nl}: array '{name}' skipped (arrays are not read)",
                self.file
            ));
            self.skip_statement();
            return Ok(());
        }
        let wanted = matches!(
            tyl.as_str(),
            "robtarget" | "speeddata" | "zonedata" | "wobjdata" | "tooldata"
        );
        if self.is_punct(":=") && wanted {
            self.next();
            let v = self.value(0)?;
            self.expect(";", &format!("';' after the value of {name}"))?;
            m.decls.push((tyl, name.to_ascii_lowercase(), v, nl, nc));
        } else {
            self.skip_statement();
        }
        Ok(())
    }

    /// Statements up to one of `ends` (consumed, with an optional `;`); returns them and the
    /// end word (lower case). `opened` names what is being closed, for the error at the end of
    /// the file.
    fn block(
        &mut self,
        m: &mut Module,
        ends: &[&str],
        opened: (&str, usize),
        depth: usize,
    ) -> Result<(Vec<Stmt>, String)> {
        let mut out = Vec::new();
        loop {
            let t = self.peek().clone();
            match &t.tok {
                Tok::Eof => {
                    let want: Vec<String> = ends.iter().map(|e| e.to_uppercase()).collect();
                    return Err(perr(
                        self.file,
                        t.line,
                        t.col,
                        format!(
                            "expected {} to close the {} opened at line {}, found end of file",
                            want.join(" or "),
                            opened.0,
                            opened.1
                        ),
                    ));
                }
                Tok::Ident(w) => {
                    let wl = w.to_ascii_lowercase();
                    if ends.contains(&wl.as_str()) {
                        self.next();
                        if self.is_punct(";") {
                            self.next();
                        }
                        return Ok((out, wl));
                    }
                    if let Some(s) = self.stmt(m, depth)? {
                        out.push(s);
                    }
                }
                _ => self.skip_statement(),
            }
        }
    }

    /// One statement starting at an identifier.
    fn stmt(&mut self, m: &mut Module, depth: usize) -> Result<Option<Stmt>> {
        let t = self.peek().clone();
        let Tok::Ident(word) = &t.tok else {
            self.skip_statement();
            return Ok(None);
        };
        if depth > 64 {
            return Err(self.err_here("control flow nested less than 64 deep"));
        }
        let w = word.to_ascii_lowercase();
        match w.as_str() {
            "if" => self.if_stmt(m, &t, depth),
            "test" => self.test_stmt(m, &t, depth),
            "for" | "while" => self.loop_stmt(m, &t, &w, depth),
            "movel" | "movej" | "movec" => {
                self.next();
                Ok(Some(Stmt::Move(self.move_stmt(
                    word.clone(),
                    t.line,
                    t.col,
                )?)))
            }
            "const" | "pers" | "var" => {
                self.decl(m)?;
                Ok(None)
            }
            "local" | "task" => {
                self.next();
                Ok(None)
            }
            _ => {
                self.next();
                // A label `name:`.
                if self.is_punct(":") {
                    self.next();
                    return Ok(None);
                }
                self.skip_statement();
                Ok(Some(Stmt::Word {
                    name: word.clone(),
                    line: t.line,
                    col: t.col,
                }))
            }
        }
    }

    /// `IF … ENDIF` (its arms) or the compact `IF cond instruction;` (not executed), at `t`.
    fn if_stmt(&mut self, m: &mut Module, t: &Token, depth: usize) -> Result<Option<Stmt>> {
        self.next();
        // `IF cond THEN … ENDIF`, or the compact `IF cond instruction;`.
        loop {
            match &self.peek().tok {
                Tok::Ident(x) if x.eq_ignore_ascii_case("then") => {
                    self.next();
                    break;
                }
                Tok::Punct(x) if x == ";" => {
                    self.next();
                    return Ok(Some(Stmt::Word {
                        name: "IF (compact, not executed)".into(),
                        line: t.line,
                        col: t.col,
                    }));
                }
                Tok::Eof => return Err(self.err_here("THEN after the IF condition")),
                _ => {
                    self.next();
                }
            }
        }
        let mut arms = Vec::new();
        let mut complete = false;
        let ends = ["elseif", "else", "endif"];
        let (mut body, mut end) = self.block(m, &ends, ("IF", t.line), depth + 1)?;
        loop {
            arms.push(body);
            match end.as_str() {
                "elseif" => {
                    self.skip_to_word("then", "THEN after the ELSEIF condition")?;
                    (body, end) = self.block(m, &ends, ("IF", t.line), depth + 1)?;
                }
                "else" => {
                    complete = true;
                    (body, end) = self.block(m, &["endif"], ("IF", t.line), depth + 1)?;
                }
                _ => break,
            }
        }
        Ok(Some(Stmt::Branch {
            kind: "IF",
            line: t.line,
            col: t.col,
            arms,
            complete,
        }))
    }

    /// `TEST … CASE … DEFAULT … ENDTEST` at `t`: its case arms.
    fn test_stmt(&mut self, m: &mut Module, t: &Token, depth: usize) -> Result<Option<Stmt>> {
        self.next();
        self.skip_line(t.line);
        let ends = ["case", "default", "endtest"];
        let (_, mut end) = self.block(m, &ends, ("TEST", t.line), depth + 1)?;
        let mut arms = Vec::new();
        let mut complete = false;
        while end != "endtest" {
            complete |= end == "default";
            while !matches!(self.peek().tok, Tok::Eof) && !self.is_punct(":") {
                self.next();
            }
            self.expect(":", "':' after CASE or DEFAULT")?;
            let (body, e) = self.block(m, &ends, ("TEST", t.line), depth + 1)?;
            arms.push(body);
            end = e;
        }
        Ok(Some(Stmt::Branch {
            kind: "TEST",
            line: t.line,
            col: t.col,
            arms,
            complete,
        }))
    }

    /// `FOR … ENDFOR` or `WHILE … ENDWHILE` (`w`, lower case) at `t`.
    fn loop_stmt(
        &mut self,
        m: &mut Module,
        t: &Token,
        w: &str,
        depth: usize,
    ) -> Result<Option<Stmt>> {
        self.next();
        self.skip_to_word("do", &format!("DO after the {} head", w.to_uppercase()))?;
        let (kind, end) = if w == "for" {
            ("FOR", "endfor")
        } else {
            ("WHILE", "endwhile")
        };
        let (body, _) = self.block(m, &[end], (kind, t.line), depth + 1)?;
        Ok(Some(Stmt::Loop {
            kind,
            line: t.line,
            body,
        }))
    }

    /// `PROC name(…) … ENDPROC` (also `FUNC type name(…)` and `TRAP name`), the keyword next.
    fn routine(&mut self, m: &mut Module) -> Result<()> {
        let t = self.next();
        let kw = match &t.tok {
            Tok::Ident(w) => w.to_ascii_lowercase(),
            _ => unreachable!("routine() is called at PROC, FUNC or TRAP"),
        };
        if kw == "func" {
            self.ident("the return type after FUNC")?;
        }
        let (name, line, _) = self.ident(&format!("a name after {}", kw.to_uppercase()))?;
        if self.is_punct("(") {
            let mut depth = 0usize;
            loop {
                match &self.peek().tok {
                    Tok::Eof => return Err(self.err_here("')' to close the parameter list")),
                    Tok::Punct(p) if p == "(" => depth += 1,
                    Tok::Punct(p) if p == ")" => {
                        depth -= 1;
                        if depth == 0 {
                            self.next();
                            break;
                        }
                    }
                    _ => {}
                }
                self.next();
            }
        }
        let end = format!("end{kw}");
        let opened = format!("{} {name}", kw.to_uppercase());
        let ends = [end.as_str(), "error", "undo", "backward"];
        let (body, mut e) = self.block(m, &ends, (&opened, line), 0)?;
        // Error, undo and backward handlers are not run on the path.
        while e != end {
            (_, e) = self.block(m, &ends, (&opened, line), 0)?;
        }
        m.routines.push(Routine { name, line, body });
        Ok(())
    }
}

fn parse_module(file: &str, text: &str) -> Result<Module> {
    let toks = lex(file, text)?;
    let mut p = Parser { file, toks, i: 0 };
    let mut m = Module {
        decls: Vec::new(),
        routines: Vec::new(),
        top: Vec::new(),
        notes: Vec::new(),
    };
    loop {
        let t = p.peek().clone();
        match &t.tok {
            Tok::Eof => break,
            Tok::Ident(word) => match word.to_ascii_lowercase().as_str() {
                "module" | "endmodule" | "endproc" | "endfunc" | "endtrap" | "endif" | "endfor"
                | "endwhile" | "endtest" | "else" | "elseif" => p.skip_line(t.line),
                "record" => {
                    p.next();
                    p.block(&mut m, &["endrecord"], ("RECORD", t.line), 0)?;
                }
                "proc" | "func" | "trap" => p.routine(&mut m)?,
                _ => {
                    if let Some(s) = p.stmt(&mut m, 0)? {
                        m.top.push(s);
                    }
                }
            },
            _ => p.skip_statement(),
        }
    }
    Ok(m)
}

/// The moves a controller runs, in order, and what the reader noted on the way.
struct Run<'a> {
    file: &'a str,
    routines: HashMap<String, &'a Routine>,
    moves: Vec<&'a MoveStmt>,
    stack: Vec<(String, usize)>,
    skipped: BTreeSet<String>,
    notes: Vec<String>,
    loops: BTreeSet<usize>,
    all: &'a [Routine],
}

impl<'a> Run<'a> {
    fn routine(&self, name: &str) -> Option<&'a Routine> {
        self.routines.get(&name.to_ascii_lowercase()).copied()
    }

    /// Whether the routine `name` reaches a move (through its calls too).
    fn reaches_moves(&self, name: &str, seen: &mut Vec<String>) -> bool {
        let n = name.to_ascii_lowercase();
        if seen.contains(&n) {
            return false;
        }
        seen.push(n);
        match self.routine(name) {
            Some(r) => !self.signature(&r.body, seen).is_empty(),
            None => false,
        }
    }

    /// What a branch arm reaches: its own moves (by line) and the procedures it calls that
    /// reach moves (with the lines of the calls).
    fn signature(&self, body: &[Stmt], seen: &mut Vec<String>) -> Vec<(String, usize)> {
        let mut out = Vec::new();
        for s in body {
            match s {
                Stmt::Move(m) => out.push((format!("a {} at line {}", m.instr, m.line), m.line)),
                Stmt::Word { name, line, .. } => {
                    if self.routine(name).is_some() && self.reaches_moves(name, &mut seen.clone()) {
                        out.push((
                            self.routine(name).map_or(name.clone(), |r| r.name.clone()),
                            *line,
                        ));
                    }
                }
                Stmt::Branch { arms, .. } => {
                    for a in arms {
                        out.extend(self.signature(a, seen));
                    }
                }
                Stmt::Loop { body, .. } => out.extend(self.signature(body, seen)),
            }
        }
        out
    }

    fn procedures_list(&self) -> String {
        self.all
            .iter()
            .map(|r| {
                format!(
                    "{} (line {}, {} moves)",
                    r.name,
                    r.line,
                    count_moves(&r.body)
                )
            })
            .collect::<Vec<_>>()
            .join(", ")
    }

    fn run(&mut self, body: &'a [Stmt]) -> Result<()> {
        for s in body {
            match s {
                Stmt::Move(m) => self.moves.push(m),
                Stmt::Word { name, line, col } => {
                    if let Some(r) = self.routine(name) {
                        self.call(r, *line, *col)?;
                    } else {
                        self.skipped.insert(name.clone());
                    }
                }
                Stmt::Loop { kind, line, body } => {
                    if self.loops.insert(*line) {
                        self.notes.push(format!(
                            "{}:{line}: {kind} loop: its body is read once (loops are not repeated)",
                            self.file
                        ));
                    }
                    self.run(body)?;
                }
                Stmt::Branch {
                    kind,
                    line,
                    col,
                    arms,
                    complete,
                } => {
                    let mut sigs: Vec<Vec<String>> = arms
                        .iter()
                        .map(|a| {
                            self.signature(a, &mut Vec::new())
                                .into_iter()
                                .map(|(n, _)| n)
                                .collect()
                        })
                        .collect();
                    if !complete {
                        sigs.push(Vec::new());
                    }
                    if sigs.iter().all(|s| *s == sigs[0]) {
                        if let (Some(a), false) = (arms.first(), sigs[0].is_empty()) {
                            self.run(a)?;
                        }
                        continue;
                    }
                    return Err(self.undecidable(kind, (*line, *col), arms, *complete));
                }
            }
        }
        Ok(())
    }

    /// The error for a branch whose arms reach different moves or calls: the reader cannot
    /// tell which one the controller runs.
    fn undecidable(
        &self,
        kind: &str,
        (line, col): (usize, usize),
        arms: &[Vec<Stmt>],
        complete: bool,
    ) -> Error {
        let mut reached: Vec<String> = Vec::new();
        for a in arms {
            for (n, l) in self.signature(a, &mut Vec::new()) {
                let item = if n.starts_with("a Move") {
                    n
                } else {
                    format!("{n} (called at {}:{l})", self.file)
                };
                if !reached.contains(&item) {
                    reached.push(item);
                }
            }
        }
        if !complete {
            reached.push("nothing (no ELSE/DEFAULT)".into());
        }
        let within = self
            .stack
            .last()
            .map_or(String::new(), |(n, _)| format!(" in {n}"));
        perr(
            self.file,
            line,
            col,
            format!(
                "the {kind}{within} chooses at run time between {}: the reader \
                 cannot tell which the controller runs; name the procedure to read \
                 as the entry. Procedures: {}",
                reached.join(", "),
                self.procedures_list()
            ),
        )
    }

    /// The procedure to run from: `entry` (which must exist) when given, else `main` if any.
    fn entry_routine(&self, entry: Option<&str>) -> Result<Option<&'a Routine>> {
        let file = self.file;
        Ok(match entry {
            Some(name) => match self.routine(name) {
                Some(r) => Some(r),
                None => {
                    return Err(Error::Invalid(format!(
                        "{file}: no procedure named '{name}' to read as the entry: expected one of \
                         {}",
                        if self.all.is_empty() {
                            "them, but the module has none".to_string()
                        } else {
                            self.procedures_list()
                        }
                    )))
                }
            },
            None => self.routine("main"),
        })
    }

    fn call(&mut self, r: &'a Routine, line: usize, col: usize) -> Result<()> {
        let key = r.name.to_ascii_lowercase();
        if self.stack.iter().any(|(n, _)| n.eq_ignore_ascii_case(&key)) {
            let chain: Vec<String> = self
                .stack
                .iter()
                .map(|(n, _)| n.clone())
                .chain(std::iter::once(r.name.clone()))
                .collect();
            return Err(perr(
                self.file,
                line,
                col,
                format!(
                    "recursive call of {}: {}; a path reader cannot unroll recursion: expected \
                     procedures that do not call themselves",
                    r.name,
                    chain.join(" → ")
                ),
            ));
        }
        if self.stack.len() >= MAX_CALL_DEPTH {
            return Err(perr(
                self.file,
                line,
                col,
                format!(
                    "calls nested deeper than {MAX_CALL_DEPTH} procedures (calling {}): expected \
                     a shallower call chain",
                    r.name
                ),
            ));
        }
        self.stack.push((r.name.clone(), line));
        self.run(&r.body)?;
        self.stack.pop();
        Ok(())
    }
}

/// Every move of the module in file order, control flow not executed (a module with no main
/// and one procedure with moves).
fn flatten<'a>(body: &'a [Stmt], out: &mut Vec<&'a MoveStmt>, skipped: &mut BTreeSet<String>) {
    for s in body {
        match s {
            Stmt::Move(m) => out.push(m),
            Stmt::Word { name, .. } => {
                skipped.insert(name.clone());
            }
            Stmt::Branch { kind, arms, .. } => {
                skipped.insert(format!("{kind} (control flow not executed)"));
                for a in arms {
                    flatten(a, out, skipped);
                }
            }
            Stmt::Loop { kind, body, .. } => {
                skipped.insert(format!("{kind} (control flow not executed)"));
                flatten(body, out, skipped);
            }
        }
    }
}

/// The moves the controller runs from the entry: `entry` when given, else `main`, else (no
/// `main`) every move in file order when at most one procedure has moves.
struct Executed<'a> {
    moves: Vec<&'a MoveStmt>,
    entry: Option<String>,
    skipped: BTreeSet<String>,
    notes: Vec<String>,
}

fn execute<'a>(file: &'a str, m: &'a Module, entry: Option<&str>) -> Result<Executed<'a>> {
    let mut run = Run {
        file,
        routines: HashMap::new(),
        moves: Vec::new(),
        stack: Vec::new(),
        skipped: BTreeSet::new(),
        notes: Vec::new(),
        loops: BTreeSet::new(),
        all: &m.routines,
    };
    for r in &m.routines {
        if let Some(first) = run.routines.insert(r.name.to_ascii_lowercase(), r) {
            return Err(perr(
                file,
                r.line,
                1,
                format!(
                    "procedure '{}' is declared twice (first on line {}): rename one",
                    r.name, first.line
                ),
            ));
        }
    }
    let chosen = run.entry_routine(entry)?;
    let mut moves = Vec::new();
    let mut skipped = BTreeSet::new();
    let entry_name;
    match chosen {
        Some(r) => {
            entry_name = Some(r.name.clone());
            run.call(r, r.line, 1)?;
            moves = std::mem::take(&mut run.moves);
            skipped = std::mem::take(&mut run.skipped);
        }
        None => {
            let with_moves: Vec<&Routine> = m
                .routines
                .iter()
                .filter(|r| count_moves(&r.body) > 0)
                .collect();
            if with_moves.len() > 1 {
                return Err(Error::Invalid(format!(
                    "{file}: no PROC main and {} procedures with moves: the reader cannot tell \
                     which the controller runs; name the procedure to read as the entry. \
                     Procedures: {}",
                    with_moves.len(),
                    run.procedures_list()
                )));
            }
            entry_name = with_moves.first().map(|r| r.name.clone());
            flatten(&m.top, &mut moves, &mut skipped);
            for r in &m.routines {
                flatten(&r.body, &mut moves, &mut skipped);
            }
            // Calls are not followed in this mode; a name of a routine is not an instruction
            // skipped.
            skipped.retain(|s| run.routine(s).is_none());
        }
    }
    Ok(Executed {
        moves,
        entry: entry_name,
        skipped,
        notes: run.notes,
    })
}

/// A pose `[[x, y, z], [q1, q2, q3, q4]]` (mm, quaternion `[w, x, y, z]`) as a frame in m;
/// `None` when the value is not one or the quaternion is zero.
fn pose_of(v: &Value) -> Option<Frame> {
    let Value::Agg(items, _, _) = v else {
        return None;
    };
    let p = nums_of(items.first()?)?;
    let q = nums_of(items.get(1)?)?;
    if p.len() != 3 || q.len() != 4 {
        return None;
    }
    let n = (q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]).sqrt();
    if !(n.is_finite() && n > 1e-9) {
        return None;
    }
    let (w, x, y, z) = (q[0] / n, q[1] / n, q[2] / n, q[3] / n);
    let rot = M3::new(
        1.0 - 2.0 * (y * y + z * z),
        2.0 * (x * y - w * z),
        2.0 * (x * z + w * y),
        2.0 * (x * y + w * z),
        1.0 - 2.0 * (x * x + z * z),
        2.0 * (y * z - w * x),
        2.0 * (x * z - w * y),
        2.0 * (y * z + w * x),
        1.0 - 2.0 * (x * x + y * y),
    );
    Some(Frame::new(rot, V3::new(p[0], p[1], p[2]) * M_PER_MM))
}

/// The `\WObj` of a move, lower case (`wobj0` when none is given).
fn wobj_of(m: &MoveStmt) -> String {
    match m.opts.get("wobj") {
        Some(Some(Value::Ident(n, _, _))) => n.to_ascii_lowercase(),
        _ => "wobj0".into(),
    }
}

/// Parse a RAPID module; `file` names the source in messages. See the module docs.
pub fn parse_rapid(text: &str, file: &str, opts: &ReadOptions) -> Result<Toolpath> {
    let module = parse_module(file, text)?;
    let ex = execute(file, &module, opts.proc.as_deref())?;
    let skipped = ex.skipped;
    let mut notes = module.notes.clone();
    notes.extend(ex.notes);
    check_unique_decls(file, &module.decls)?;
    let decls = read_decls(file, &module.decls)?;
    let (part, shown) = part_wobj(&ex.moves);
    let tp = Toolpath {
        source: file.to_string(),
        procedures: module
            .routines
            .iter()
            .map(|r| Procedure {
                name: r.name.clone(),
                line: r.line,
                moves: count_moves(&r.body),
            })
            .collect(),
        entry: ex.entry.clone(),
        ..Default::default()
    };
    let mut rd = RapidMoves {
        file,
        decls,
        part,
        shown,
        tp,
        notes,
        started: false,
        pos: V3::zeros(),
        used_vmax: false,
        tool_note: false,
        home_lines: Vec::new(),
        other_wobjs: BTreeSet::new(),
        tools_used: Vec::new(),
    };
    for m in &ex.moves {
        rd.take_move(m)?;
    }
    rd.finish(&ex.entry, module.routines.len(), skipped)
}

/// Refuse a name declared twice, naming both lines (RAPID refuses it too).
fn check_unique_decls(file: &str, decls: &[Decl]) -> Result<()> {
    let mut seen: HashMap<&str, usize> = HashMap::new();
    for (_, name, _, l, c) in decls {
        if let Some(first) = seen.insert(name.as_str(), *l) {
            return Err(perr(
                file,
                *l,
                *c,
                format!("'{name}' is declared twice (first on line {first}): rename one"),
            ));
        }
    }
    Ok(())
}

/// The module's declared data: targets, speeds and zones, work objects and tools.
struct Decls {
    data: Data,
    /// Work object frame (uframe·oframe) and declaration line, by lower-case name.
    wobjs: HashMap<String, (Frame, usize)>,
    /// Tool data value and declaration line, by name.
    tools: HashMap<String, (Value, usize)>,
}

/// Resolve the module's data declarations in declaration order (robtargets may refer to
/// others through Offs).
fn read_decls(file: &str, decls: &[Decl]) -> Result<Decls> {
    let mut out = Decls {
        data: Data {
            robtargets: HashMap::new(),
            speeds: HashMap::new(),
            zones: HashMap::new(),
        },
        wobjs: HashMap::new(),
        tools: HashMap::new(),
    };
    for (ty, name, v, l, c) in decls {
        let data = &mut out.data;
        match ty.as_str() {
            "robtarget" => {
                let p = robtarget(file, data, v, (*l, *c))?;
                data.robtargets.insert(name.clone(), p);
            }
            "speeddata" => {
                let s = speed_of(file, data, v, (*l, *c))?;
                data.speeds.insert(name.clone(), s / M_PER_MM);
            }
            "zonedata" => {
                let z = zone_of(file, data, v, (*l, *c))?;
                data.zones.insert(name.clone(), z);
            }
            "wobjdata" => {
                // [robhold, ufprog, ufmec, uframe, oframe]
                let frames = match v {
                    Value::Agg(items, _, _) if items.len() == 5 => {
                        pose_of(&items[3]).zip(pose_of(&items[4]))
                    }
                    _ => None,
                };
                let Some((uf, of)) = frames else {
                    return Err(perr(
                        file,
                        *l,
                        *c,
                        "expected wobjdata [robhold, ufprog, ufmec, [[x,y,z],[q1,q2,q3,q4]], \
                         [[x,y,z],[q1,q2,q3,q4]]] (uframe, oframe; a non-zero quaternion)",
                    ));
                };
                out.wobjs.insert(name.clone(), (uf.compose(&of), *l));
            }
            _ => {
                out.tools.insert(name.clone(), (v.clone(), *l));
            }
        }
    }
    Ok(out)
}

/// The part frame: the work object the print moves (MoveL, MoveC) use most (the first of
/// equals); all moves when none prints. Also each work object's name as first written.
fn part_wobj(moves: &[&MoveStmt]) -> (String, HashMap<String, String>) {
    let mut shown: HashMap<String, String> = HashMap::new();
    for m in moves {
        if let Some(Some(Value::Ident(n, _, _))) = m.opts.get("wobj") {
            shown
                .entry(n.to_ascii_lowercase())
                .or_insert_with(|| n.clone());
        }
        let k = usize::from(m.instr.eq_ignore_ascii_case("movec"));
        if let Some(Value::Ident(n, _, _)) = m.args.get(k + 3).map(|a| &a.value) {
            shown
                .entry(n.to_ascii_lowercase())
                .or_insert_with(|| n.clone());
        }
    }
    let mut counts: Vec<(String, usize)> = Vec::new();
    let prints: Vec<&&MoveStmt> = moves
        .iter()
        .filter(|m| !m.instr.eq_ignore_ascii_case("movej"))
        .collect();
    let pool: Vec<&&MoveStmt> = if prints.is_empty() {
        moves.iter().collect()
    } else {
        prints
    };
    for m in pool {
        let w = wobj_of(m);
        match counts.iter_mut().find(|(n, _)| *n == w) {
            Some(c) => c.1 += 1,
            None => counts.push((w, 1)),
        }
    }
    let part = counts
        .iter()
        .fold(None::<&(String, usize)>, |best, c| match best {
            Some(b) if b.1 >= c.1 => Some(b),
            _ => Some(c),
        })
        .map_or("wobj0".to_string(), |c| c.0.clone());
    (part, shown)
}

/// The executed moves being turned into a toolpath in the part frame.
struct RapidMoves<'a> {
    file: &'a str,
    decls: Decls,
    /// The part's work object (lower case).
    part: String,
    /// Work object names as first written, by lower-case name.
    shown: HashMap<String, String>,
    tp: Toolpath,
    notes: Vec<String>,
    started: bool,
    pos: V3,
    used_vmax: bool,
    tool_note: bool,
    home_lines: Vec<usize>,
    other_wobjs: BTreeSet<String>,
    tools_used: Vec<(String, usize)>,
}

impl RapidMoves<'_> {
    /// A work object's name as the program writes it.
    fn show(&self, n: &str) -> String {
        self.shown.get(n).cloned().unwrap_or_else(|| n.to_string())
    }

    /// A work object's frame (wobj0 is the world).
    fn frame_of(&self, w: &str) -> Option<Frame> {
        if w == "wobj0" {
            Some(Frame::identity())
        } else {
            self.decls.wobjs.get(w).map(|f| f.0)
        }
    }

    /// The transform from a move's work object into the part frame; None for a wobj0 move
    /// while the print uses another work object (a home position, skipped).
    fn part_transform(&mut self, m: &MoveStmt, wobj: &str) -> Result<Option<Frame>> {
        if wobj == self.part {
            return Ok(Some(Frame::identity()));
        }
        if wobj == "wobj0" {
            self.home_lines.push(m.line);
            return Ok(None);
        }
        match (self.frame_of(&self.part), self.frame_of(wobj)) {
            (Some(p), Some(w)) => {
                self.other_wobjs.insert(wobj.to_string());
                Ok(Some(p.inverse().compose(&w)))
            }
            (_, None) => Err(perr(
                self.file,
                m.line,
                m.col,
                format!(
                    "undefined wobjdata '{}': its targets cannot be put in the part \
                     frame ({}): expected wobj0 or a wobjdata declared in the module",
                    self.show(wobj),
                    self.show(&self.part)
                ),
            )),
            (None, _) => Err(perr(
                self.file,
                m.line,
                m.col,
                format!(
                    "the move is in work object '{w}' and the print in '{p}', which is \
                     not declared in the module: expected a wobjdata {p} to put '{w}' \
                     targets in the part frame",
                    w = self.show(wobj),
                    p = self.show(&self.part)
                ),
            )),
        }
    }

    /// Take one executed move: check its arguments, put its target in the part frame and
    /// append it to the toolpath (the first one is the start point).
    fn take_move(&mut self, m: &MoveStmt) -> Result<()> {
        let file = self.file;
        let instr = m.instr.to_ascii_lowercase();
        let is_c = instr == "movec";
        check_move_arity(file, m, is_c)?;
        let wobj = wobj_of(m);
        let Some(to_part) = self.part_transform(m, &wobj)? else {
            return Ok(());
        };
        let at = (m.line, m.col);
        let k = usize::from(is_c);
        if let Value::Ident(t, _, _) = &m.args[k + 3].value {
            let t = t.to_ascii_lowercase();
            if !self.tools_used.iter().any(|(n, _)| *n == t) {
                self.tools_used.push((t, m.line));
            }
        }
        let to = to_part.apply(&robtarget(file, &self.decls.data, &m.args[k].value, at)?);
        let (speed, zone) = self.speed_and_zone(m, k)?;
        self.tool_note = true;
        if !self.started {
            if is_c {
                return Err(perr(
                    file,
                    m.line,
                    m.col,
                    "MoveC cannot be the first move: expected a MoveL or MoveJ to its start point",
                ));
            }
            self.started = true;
            self.tp.start = to;
            self.pos = to;
            return Ok(());
        }
        let kind = if is_c {
            let via = to_part.apply(&robtarget(file, &self.decls.data, &m.args[0].value, at)?);
            arc_through(file, m, &self.pos, &via, &to)?
        } else {
            MoveKind::Line
        };
        let mv = Move {
            kind,
            end: to,
            speed,
            zone,
            print: instr != "movej",
            line: m.line,
        };
        if mv.length(&self.pos) > 1e-12 {
            self.tp.moves.push(mv);
            self.pos = to;
        }
        Ok(())
    }

    /// A move's speed and zone: its speeddata and zonedata, then its \V, \T, \Z and \Inpos
    /// switches.
    fn speed_and_zone(&mut self, m: &MoveStmt, k: usize) -> Result<(f64, Zone)> {
        let file = self.file;
        let at = (m.line, m.col);
        let data = &self.decls.data;
        let mut speed = speed_of(file, data, &m.args[k + 1].value, at)?;
        if matches!(&m.args[k + 1].value, Value::Ident(n, _, _) if n.eq_ignore_ascii_case("vmax")) {
            self.used_vmax = true;
        }
        let mut zone = zone_of(file, data, &m.args[k + 2].value, at)?;
        if let Some(Some(v)) = m.opts.get("v") {
            match num_of(v) {
                Some(s) if s > 0.0 => speed = s * M_PER_MM,
                _ => {
                    return Err(perr(
                        file,
                        m.line,
                        m.col,
                        "expected \\V:= a positive speed in mm/s",
                    ))
                }
            }
        }
        if m.opts.contains_key("t") {
            self.notes.push(format!(
                "{file}:{}: \\T (move time) ignored; speeddata used",
                m.line
            ));
        }
        if let Some(Some(v)) = m.opts.get("z") {
            match num_of(v) {
                Some(z) if z >= 0.0 => zone = Zone::Blend(z * M_PER_MM),
                _ => {
                    return Err(perr(
                        file,
                        m.line,
                        m.col,
                        "expected \\Z:= a zone size in mm",
                    ))
                }
            }
        }
        if m.opts.contains_key("inpos") {
            zone = Zone::Fine;
        }
        Ok((speed, zone))
    }

    /// The toolpath with its warnings: entry, part frame, other work objects, skipped home
    /// moves, tool frames, vmax, skipped instructions, then the reader's notes.
    fn finish(
        mut self,
        entry: &Option<String>,
        procedures: usize,
        mut skipped: BTreeSet<String>,
    ) -> Result<Toolpath> {
        let file = self.file;
        if let Some(e) = entry {
            let n = procedures;
            if n > 1 {
                self.tp.warnings.push(format!(
                    "{file}: read from PROC {e} as the controller runs it (its calls followed), \
                     {n} procedures in the module"
                ));
            }
        }
        self.frame_warnings();
        self.tool_frame_warnings();
        if self.used_vmax {
            self.tp.warnings.push(format!(
                "{file}: vmax taken as {VMAX_MM_S} mm/s; the real value depends on the robot"
            ));
        }
        if !skipped.is_empty() {
            self.tp.warnings.push(format!(
                "{file}: skipped instructions: {}",
                std::mem::take(&mut skipped)
                    .into_iter()
                    .collect::<Vec<_>>()
                    .join(", ")
            ));
        }
        self.tp.warnings.extend(self.notes);
        Ok(self.tp)
    }

    /// Say which frame the targets were taken in, which other work objects were moved into
    /// it, and which wobj0 moves were skipped.
    fn frame_warnings(&mut self) {
        let file = self.file;
        let part = self.show(&self.part);
        if self.tool_note {
            let frame = if self.part == "wobj0" {
                "the work object's frame (= the part frame)".to_string()
            } else {
                format!(
                    "work object {part}'s frame (= the part frame, the one the print moves use)"
                )
            };
            self.tp.warnings.push(format!(
                "{file}: targets taken in {frame}; orientations dropped (vertical nozzle assumed)"
            ));
        }
        if !self.other_wobjs.is_empty() {
            let others = self
                .other_wobjs
                .iter()
                .map(|w| self.show(w))
                .collect::<Vec<_>>()
                .join(", ");
            self.tp.warnings.push(format!(
                "{file}: targets in {others} put in the part frame {part} through their wobjdata \
                 (uframe·oframe)"
            ));
        }
        if !self.home_lines.is_empty() {
            let lines: Vec<String> = self.home_lines.iter().map(|l| l.to_string()).collect();
            self.tp.warnings.push(format!(
                "{file}: line {}: move(s) in wobj0 while the print uses work object {part}: not part \
                 points (e.g. a home position), skipped",
                lines.join(", "),
            ));
        }
    }

    /// Warn about each used tool whose tool frame is not the identity.
    fn tool_frame_warnings(&mut self) {
        let file = self.file;
        for (t, line) in &self.tools_used {
            let Some((v, decl_line)) = self.decls.tools.get(t) else {
                continue;
            };
            let tframe = match v {
                Value::Agg(items, _, _) => items.get(1).and_then(pose_of),
                _ => None,
            };
            if let Some(f) = tframe {
                let identity = f.pos.norm() < 1e-9 && (f.rot - M3::identity()).norm() < 1e-9;
                if !identity {
                    self.tp.warnings.push(format!(
                        "{file}:{line}: tool {} (declared on line {decl_line}) has a tool frame \
                         that is not the identity (offset {:.1} mm from the flange): targets are \
                         read as the nozzle tip's positions and the robot's own nozzle model is kept",
                        self.show(t),
                        f.pos.norm() / M_PER_MM
                    ));
                }
            }
        }
    }
}

/// Refuse a move whose argument count does not fit its instruction.
fn check_move_arity(file: &str, m: &MoveStmt, is_c: bool) -> Result<()> {
    let need = if is_c { 5 } else { 4 };
    if m.args.len() != need {
        return Err(perr(
            file,
            m.end_line,
            m.end_col,
            format!(
                "{}: expected {need} arguments ({}), found {}",
                m.instr,
                if is_c {
                    "CirPoint, ToPoint, Speed, Zone, Tool"
                } else {
                    "ToPoint, Speed, Zone, Tool"
                },
                m.args.len()
            ),
        ));
    }
    Ok(())
}

/// The arc of a MoveC from `pos` through `via` to `to`.
fn arc_through(file: &str, m: &MoveStmt, pos: &V3, via: &V3, to: &V3) -> Result<MoveKind> {
    match circle_through(pos, via, to) {
        Some((centre, normal, radius, sweep)) => Ok(MoveKind::Arc {
            centre,
            normal,
            radius,
            sweep,
            axial: 0.0,
        }),
        None => Err(perr(
            file,
            m.line,
            m.col,
            "MoveC: start, circle point and end point are collinear or coincide: \
             expected three distinct points on a circle",
        )),
    }
}

/// One move of a RAPID module as a controller takes it: the instruction, the robtarget's
/// position (mm), orientation quaternion `[q1, q2, q3, q4]`, configuration
/// `[cf1, cf4, cf6, cfx]`, the work object named by `\WObj` and the source line.
#[derive(Clone, Debug, PartialEq)]
pub struct RapidTarget {
    /// `MoveL`, `MoveJ` or `MoveC` (as written).
    pub instr: String,
    /// Position, mm, in the move's work object.
    pub pos_mm: [f64; 3],
    /// Orientation quaternion `[q1, q2, q3, q4]` = `[w, x, y, z]`.
    pub quat: [f64; 4],
    /// Configuration data `[cf1, cf4, cf6, cfx]`.
    pub conf: [i32; 4],
    /// The `\WObj` argument's name (`wobj0` when none is given).
    pub wobj: String,
    /// Source line.
    pub line: usize,
}

/// What a RAPID module hands a controller beyond the path ([`parse_rapid`] reads the path):
/// module names, inline robtargets of the moves with their configuration, the declared
/// `jointtarget`s (deg), the `MoveAbsJ` targets, and the last `ConfL` and `SingArea` switches.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct RapidProgram {
    /// `MODULE` names, in order.
    pub modules: Vec<String>,
    /// Moves with inline or declared robtargets, in the order the controller runs them.
    pub targets: Vec<RapidTarget>,
    /// Declared `jointtarget`s: name (lower case) and robot axes, deg.
    pub jointtargets: Vec<(String, Vec<f64>)>,
    /// Targets of `MoveAbsJ`, in order (names, lower case).
    pub abs_moves: Vec<String>,
    /// `ConfL \On` (true) or `\Off` (false), the last one given.
    pub conf_l: Option<bool>,
    /// The last `SingArea` switch (`wrist`, `off`, …, lower case).
    pub sing_area: Option<String>,
    /// Comment lines (`!`) before the first `MODULE` (a controller refuses them there).
    pub comments_before_module: usize,
}

fn nums_of(v: &Value) -> Option<Vec<f64>> {
    match v {
        Value::Agg(items, _, _) => items.iter().map(num_of).collect(),
        _ => None,
    }
}

fn target_parts(v: &Value) -> Option<([f64; 3], [f64; 4], [i32; 4])> {
    let Value::Agg(items, _, _) = v else {
        return None;
    };
    let p = nums_of(items.first()?)?;
    let q = nums_of(items.get(1)?)?;
    let c = nums_of(items.get(2)?)?;
    if p.len() != 3 || q.len() != 4 || c.len() != 4 {
        return None;
    }
    Some((
        [p[0], p[1], p[2]],
        [q[0], q[1], q[2], q[3]],
        [c[0] as i32, c[1] as i32, c[2] as i32, c[3] as i32],
    ))
}

/// Read a RAPID module for what a controller needs (see [`RapidProgram`]); `file` names the
/// source in messages. The moves are taken in the order the controller runs them from `main`
/// (as [`parse_rapid`]; see [`read_program_entry`] to name another entry). Errors where the
/// module does not parse (as [`parse_rapid`]) or a move's robtarget is not
/// `[[x, y, z], [q1, q2, q3, q4], [cf1, cf4, cf6, cfx], [eax…]]`.
pub fn read_program(text: &str, file: &str) -> Result<RapidProgram> {
    read_program_entry(text, file, None)
}

/// [`read_program`] from the procedure `entry` instead of `main` (as [`ReadOptions::proc`]).
pub fn read_program_entry(text: &str, file: &str, entry: Option<&str>) -> Result<RapidProgram> {
    let module = parse_module(file, text)?;
    let ex = execute(file, &module, entry)?;
    let toks = lex(file, text)?;
    let mut scan = ProgramScan {
        file,
        prog: RapidProgram::default(),
        robtargets: HashMap::new(),
        by_place: HashMap::new(),
    };
    scan.prog.comments_before_module = comments_before_module(text);
    let mut p = Parser { file, toks, i: 0 };
    loop {
        let t = p.peek().clone();
        match &t.tok {
            Tok::Eof => break,
            Tok::Ident(word) => scan.word(&mut p, &t, word)?,
            _ => p.skip_statement(),
        }
    }
    let ProgramScan {
        mut prog, by_place, ..
    } = scan;
    for m in &ex.moves {
        match by_place.get(&(m.line, m.col)) {
            Some(Some(t)) => prog.targets.push(t.clone()),
            Some(None) => {
                return Err(perr(
                    file,
                    m.line,
                    m.col,
                    "expected a robtarget [[x,y,z],[q1,q2,q3,q4],[cf1,cf4,cf6,cfx],[eax…]]",
                ))
            }
            None => {}
        }
    }
    Ok(prog)
}

/// The `!` comment lines before the first MODULE line.
fn comments_before_module(text: &str) -> usize {
    let mut n = 0;
    for l in text.lines() {
        let t = l.trim_start();
        if t.to_ascii_lowercase().starts_with("module") {
            break;
        }
        n += usize::from(t.starts_with('!'));
    }
    n
}

/// A pass over a module's text in file order, collecting what a controller needs.
struct ProgramScan<'a> {
    file: &'a str,
    prog: RapidProgram,
    /// Declared robtarget values, by lower-case name.
    robtargets: HashMap<String, Value>,
    /// Each move's target by its place (line, column); None when it is no full robtarget.
    by_place: HashMap<(usize, usize), Option<RapidTarget>>,
}

impl ProgramScan<'_> {
    /// Take the statement starting with the word `word` at token `t`.
    fn word(&mut self, p: &mut Parser, t: &Token, word: &str) -> Result<()> {
        let w = word.to_ascii_lowercase();
        match w.as_str() {
            "module" => {
                p.next();
                let (name, _, _) = p.ident("a module name")?;
                self.prog.modules.push(name);
                p.skip_line(t.line);
            }
            "const" | "pers" | "var" => {
                p.next();
                self.decl(p, t)?;
            }
            "movel" | "movej" | "movec" | "moveabsj" => {
                p.next();
                let m = p.move_stmt(word.to_string(), t.line, t.col)?;
                self.move_target(&m, &w);
            }
            "confl" | "singarea" => {
                p.next();
                let mut opts = HashMap::new();
                p.switches(&mut opts)?;
                p.expect(";", &format!("';' after {word}"))?;
                let on = opts.keys().next().cloned().unwrap_or_default();
                if w == "confl" {
                    self.prog.conf_l = Some(on == "on");
                } else {
                    self.prog.sing_area = Some(on);
                }
            }
            "proc" | "endproc" | "endmodule" | "func" | "endfunc" | "trap" | "endtrap" | "if"
            | "elseif" | "else" | "endif" | "for" | "endfor" | "while" | "endwhile" | "test"
            | "case" | "default" | "endtest" => {
                p.skip_line(t.line);
            }
            "local" | "task" => {
                p.next();
            }
            _ => p.skip_statement(),
        }
        Ok(())
    }

    /// A data declaration after CONST/PERS/VAR: robtargets and jointtargets are kept.
    fn decl(&mut self, p: &mut Parser, t: &Token) -> Result<()> {
        let (ty, _, _) = p.ident("a data type after CONST/PERS/VAR")?;
        let (name, _, _) = p.ident("a data name")?;
        let tyl = ty.to_ascii_lowercase();
        if !(p.is_punct(":=") && matches!(tyl.as_str(), "robtarget" | "jointtarget")) {
            p.skip_statement();
            return Ok(());
        }
        p.next();
        let v = p.value(0)?;
        p.expect(";", &format!("';' after the value of {name}"))?;
        if tyl == "robtarget" {
            self.robtargets.insert(name.to_ascii_lowercase(), v);
        } else {
            let axes = match &v {
                Value::Agg(items, _, _) => items.first().and_then(nums_of),
                _ => None,
            }
            .ok_or_else(|| {
                perr(
                    self.file,
                    t.line,
                    t.col,
                    "expected a jointtarget [[j1, …], [eax…]]",
                )
            })?;
            self.prog
                .jointtargets
                .push((name.to_ascii_lowercase(), axes));
        }
        Ok(())
    }

    /// Note a move's target (`w`: the lower-case instruction) by its place.
    fn move_target(&mut self, m: &MoveStmt, w: &str) {
        if w == "moveabsj" {
            if let Some(Value::Ident(n, _, _)) = m.args.first().map(|a| &a.value) {
                self.prog.abs_moves.push(n.to_ascii_lowercase());
            }
            return;
        }
        let k = usize::from(w == "movec");
        let v = m.args.get(k).map(|a| &a.value);
        let v = match v {
            Some(Value::Ident(n, _, _)) => self.robtargets.get(&n.to_ascii_lowercase()),
            other => other,
        };
        // A move the controller does not run may have any target; one it
        // runs must have a full robtarget (checked below).
        let Some((pos_mm, quat, conf)) = v.and_then(target_parts) else {
            self.by_place.insert((m.line, m.col), None);
            return;
        };
        let wobj = match m.opts.get("wobj") {
            Some(Some(Value::Ident(n, _, _))) => n.clone(),
            _ => "wobj0".into(),
        };
        self.by_place.insert(
            (m.line, m.col),
            Some(RapidTarget {
                instr: m.instr.clone(),
                pos_mm,
                quat,
                conf,
                wobj,
                line: m.line,
            }),
        );
    }
}
