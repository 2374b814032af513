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
//! instructions are skipped and listed in one warning. Tool and work-object arguments are
//! accepted and ignored (targets are taken in the work object's frame = the part frame).
//! Control flow (`IF`, `FOR`, `WHILE`, procedure calls) is not executed: moves are read in file
//! order. Declarations may appear anywhere in the file. The first move sets the start point.
//! `MoveAbsJ` (joint targets) is skipped with a warning.

use std::collections::{BTreeSet, HashMap};

use super::{circle_through, perr, Move, MoveKind, ReadOptions, Toolpath, Zone};
use crate::error::{Error, Result};
use crate::math::V3;

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

/// Parse a RAPID module; `file` names the source in messages. See the module docs.
pub fn parse_rapid(text: &str, file: &str, _opts: &ReadOptions) -> Result<Toolpath> {
    let toks = lex(file, text)?;
    let mut p = Parser { file, toks, i: 0 };
    let mut decls: Vec<(String, String, Value, usize, usize)> = Vec::new();
    let mut moves: Vec<MoveStmt> = Vec::new();
    let mut skipped: BTreeSet<String> = BTreeSet::new();
    let mut notes: Vec<String> = Vec::new();
    loop {
        let t = p.peek().clone();
        match &t.tok {
            Tok::Eof => break,
            Tok::Ident(word) => {
                let w = word.to_ascii_lowercase();
                match w.as_str() {
                    "module" | "proc" | "func" | "trap" | "record" | "if" | "elseif" | "else"
                    | "for" | "while" | "test" | "case" | "default" | "endif" | "endfor"
                    | "endwhile" | "endtest" | "endmodule" | "endproc" | "endfunc" | "endtrap"
                    | "endrecord" => {
                        if matches!(w.as_str(), "if" | "for" | "while" | "test") {
                            skipped.insert(format!(
                                "{} (control flow not executed)",
                                w.to_uppercase()
                            ));
                        }
                        p.skip_line(t.line);
                    }
                    "local" | "task" => {
                        p.next();
                    }
                    "const" | "pers" | "var" => {
                        p.next();
                        let (ty, _, _) = p.ident("a data type after CONST/PERS/VAR")?;
                        let (name, nl, nc) = p.ident("a data name")?;
                        let tyl = ty.to_ascii_lowercase();
                        if p.is_punct("{") {
                            notes.push(format!(
                                "{file}:{nl}: array '{name}' skipped (arrays are not read)"
                            ));
                            p.skip_statement();
                            continue;
                        }
                        let wanted = matches!(tyl.as_str(), "robtarget" | "speeddata" | "zonedata");
                        if p.is_punct(":=") && wanted {
                            p.next();
                            let v = p.value(0)?;
                            p.expect(";", &format!("';' after the value of {name}"))?;
                            decls.push((tyl, name.to_ascii_lowercase(), v, nl, nc));
                        } else {
                            p.skip_statement();
                        }
                    }
                    "movel" | "movej" | "movec" => {
                        p.next();
                        let m = p.move_stmt(word.clone(), t.line, t.col)?;
                        moves.push(m);
                    }
                    _ => {
                        skipped.insert(word.clone());
                        p.skip_statement();
                    }
                }
            }
            _ => {
                p.skip_statement();
            }
        }
    }

    let mut data = Data {
        robtargets: HashMap::new(),
        speeds: HashMap::new(),
        zones: HashMap::new(),
    };
    // A name declared twice is an error naming both lines (RAPID refuses it too).
    {
        let mut seen: HashMap<&str, usize> = HashMap::new();
        for (_, name, _, l, c) in &decls {
            if let Some(first) = seen.insert(name.as_str(), *l) {
                return Err(perr(
                    file,
                    *l,
                    *c,
                    format!("'{name}' is declared twice (first on line {first}): rename one"),
                ));
            }
        }
    }
    // Robtargets may refer to others (Offs); resolve in declaration order.
    for (ty, name, v, l, c) in &decls {
        match ty.as_str() {
            "robtarget" => {
                let p = robtarget(file, &data, v, (*l, *c))?;
                data.robtargets.insert(name.clone(), p);
            }
            "speeddata" => {
                let s = speed_of(file, &data, v, (*l, *c))?;
                data.speeds.insert(name.clone(), s / M_PER_MM);
            }
            _ => {
                let z = zone_of(file, &data, v, (*l, *c))?;
                data.zones.insert(name.clone(), z);
            }
        }
    }

    let mut tp = Toolpath {
        source: file.to_string(),
        ..Default::default()
    };
    let mut started = false;
    let mut pos = V3::zeros();
    let mut used_vmax = false;
    let mut tool_note = false;
    for m in &moves {
        let instr = m.instr.to_ascii_lowercase();
        let is_c = instr == "movec";
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
        let at = (m.line, m.col);
        let k = usize::from(is_c);
        let to = robtarget(file, &data, &m.args[k].value, at)?;
        let mut speed = speed_of(file, &data, &m.args[k + 1].value, at)?;
        if matches!(&m.args[k + 1].value, Value::Ident(n, _, _) if n.eq_ignore_ascii_case("vmax")) {
            used_vmax = true;
        }
        let mut zone = zone_of(file, &data, &m.args[k + 2].value, at)?;
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
            notes.push(format!(
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
        tool_note = true;
        if !started {
            if is_c {
                return Err(perr(
                    file,
                    m.line,
                    m.col,
                    "MoveC cannot be the first move: expected a MoveL or MoveJ to its start point",
                ));
            }
            started = true;
            tp.start = to;
            pos = to;
            continue;
        }
        let kind = if is_c {
            let via = robtarget(file, &data, &m.args[0].value, at)?;
            match circle_through(&pos, &via, &to) {
                Some((centre, normal, radius, sweep)) => MoveKind::Arc {
                    centre,
                    normal,
                    radius,
                    sweep,
                    axial: 0.0,
                },
                None => {
                    return Err(perr(
                        file,
                        m.line,
                        m.col,
                        "MoveC: start, circle point and end point are collinear or coincide: \
                         expected three distinct points on a circle",
                    ))
                }
            }
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
        if mv.length(&pos) > 1e-12 {
            tp.moves.push(mv);
            pos = to;
        }
    }
    if tool_note {
        tp.warnings.push(format!(
            "{file}: tool and work-object arguments ignored: targets taken in the work object's \
             frame (= the part frame); orientations dropped (vertical nozzle assumed)"
        ));
    }
    if used_vmax {
        tp.warnings.push(format!(
            "{file}: vmax taken as {VMAX_MM_S} mm/s; the real value depends on the robot"
        ));
    }
    if !skipped.is_empty() {
        tp.warnings.push(format!(
            "{file}: skipped instructions: {}",
            skipped.into_iter().collect::<Vec<_>>().join(", ")
        ));
    }
    tp.warnings.extend(notes);
    Ok(tp)
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
    /// Moves with inline or declared robtargets, in file order.
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
/// source in messages. Errors where the module does not parse (as [`parse_rapid`]) or a move's
/// robtarget is not `[[x, y, z], [q1, q2, q3, q4], [cf1, cf4, cf6, cfx], [eax…]]`.
pub fn read_program(text: &str, file: &str) -> Result<RapidProgram> {
    let toks = lex(file, text)?;
    let mut prog = RapidProgram::default();
    for l in text.lines() {
        let t = l.trim_start();
        if t.to_ascii_lowercase().starts_with("module") {
            break;
        }
        prog.comments_before_module += usize::from(t.starts_with('!'));
    }
    let mut p = Parser { file, toks, i: 0 };
    let mut robtargets: HashMap<String, Value> = HashMap::new();
    loop {
        let t = p.peek().clone();
        match &t.tok {
            Tok::Eof => break,
            Tok::Ident(word) => {
                let w = word.to_ascii_lowercase();
                match w.as_str() {
                    "module" => {
                        p.next();
                        let (name, _, _) = p.ident("a module name")?;
                        prog.modules.push(name);
                        p.skip_line(t.line);
                    }
                    "const" | "pers" | "var" => {
                        p.next();
                        let (ty, _, _) = p.ident("a data type after CONST/PERS/VAR")?;
                        let (name, _, _) = p.ident("a data name")?;
                        let tyl = ty.to_ascii_lowercase();
                        if p.is_punct(":=") && matches!(tyl.as_str(), "robtarget" | "jointtarget") {
                            p.next();
                            let v = p.value(0)?;
                            p.expect(";", &format!("';' after the value of {name}"))?;
                            if tyl == "robtarget" {
                                robtargets.insert(name.to_ascii_lowercase(), v);
                            } else {
                                let axes = match &v {
                                    Value::Agg(items, _, _) => items.first().and_then(nums_of),
                                    _ => None,
                                }
                                .ok_or_else(|| {
                                    perr(
                                        file,
                                        t.line,
                                        t.col,
                                        "expected a jointtarget [[j1, …], [eax…]]",
                                    )
                                })?;
                                prog.jointtargets.push((name.to_ascii_lowercase(), axes));
                            }
                        } else {
                            p.skip_statement();
                        }
                    }
                    "movel" | "movej" | "movec" | "moveabsj" => {
                        p.next();
                        let m = p.move_stmt(word.clone(), t.line, t.col)?;
                        if w == "moveabsj" {
                            if let Some(Value::Ident(n, _, _)) = m.args.first().map(|a| &a.value) {
                                prog.abs_moves.push(n.to_ascii_lowercase());
                            }
                            continue;
                        }
                        let k = usize::from(w == "movec");
                        let v = m.args.get(k).map(|a| &a.value);
                        let v = match v {
                            Some(Value::Ident(n, _, _)) => robtargets.get(&n.to_ascii_lowercase()),
                            other => other,
                        };
                        let (pos_mm, quat, conf) = v.and_then(target_parts).ok_or_else(|| {
                            perr(
                                file,
                                m.line,
                                m.col,
                                "expected a robtarget [[x,y,z],[q1,q2,q3,q4],[cf1,cf4,cf6,cfx],[eax…]]",
                            )
                        })?;
                        let wobj = match m.opts.get("wobj") {
                            Some(Some(Value::Ident(n, _, _))) => n.clone(),
                            _ => "wobj0".into(),
                        };
                        prog.targets.push(RapidTarget {
                            instr: m.instr.clone(),
                            pos_mm,
                            quat,
                            conf,
                            wobj,
                            line: m.line,
                        });
                    }
                    "confl" | "singarea" => {
                        p.next();
                        let mut opts = HashMap::new();
                        p.switches(&mut opts)?;
                        p.expect(";", &format!("';' after {word}"))?;
                        let on = opts.keys().next().cloned().unwrap_or_default();
                        if w == "confl" {
                            prog.conf_l = Some(on == "on");
                        } else {
                            prog.sing_area = Some(on);
                        }
                    }
                    "proc" | "endproc" | "endmodule" => {
                        p.skip_line(t.line);
                    }
                    "local" | "task" => {
                        p.next();
                    }
                    _ => p.skip_statement(),
                }
            }
            _ => p.skip_statement(),
        }
    }
    Ok(prog)
}
