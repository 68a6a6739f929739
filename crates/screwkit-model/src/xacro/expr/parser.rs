//! The parser and evaluator of `${…}` expressions (recursive descent, one function per
//! precedence level from `ternary` down to `postfix`, evaluated as parsed; the
//! branch not taken of `a if c else b`, `and`, `or` is parsed, not evaluated): Python's
//! semantics on 64-bit integers and floats.

use super::*;

pub(crate) struct Parser<'a, 'o> {
    pub(crate) x: &'a mut Expander<'o>,
    pub(crate) tokens: Vec<Tok>,
    pub(crate) pos: usize,
    pub(crate) scope: &'a Scope,
    pub(crate) at: &'a At,
    pub(crate) src: &'a str,
    /// Above zero: parsing only, no evaluation (the branch of `a if c else b`, `and`, `or`
    /// that Python does not evaluate). Values are placeholders and nothing fails but syntax.
    pub(crate) skip: u32,
}

/// The placeholder value of an expression parsed but not evaluated.
pub(crate) const SKIPPED: Value = Value::Int(0);

impl Parser<'_, '_> {
    pub(crate) fn err(&self, m: impl std::fmt::Display) -> ModelError {
        fail(self.at, format!("${{{}}}: {m}", self.src))
    }

    pub(crate) fn peek(&self) -> Option<&Tok> {
        self.tokens.get(self.pos)
    }

    pub(crate) fn eat_op(&mut self, op: &str) -> bool {
        if matches!(self.peek(), Some(Tok::Op(o)) if *o == op) {
            self.pos += 1;
            true
        } else {
            false
        }
    }

    pub(crate) fn eat_name(&mut self, n: &str) -> bool {
        if matches!(self.peek(), Some(Tok::Name(x)) if x == n) {
            self.pos += 1;
            true
        } else {
            false
        }
    }

    /// Runs `f` one nesting level deeper ([`MAX_NESTING`]).
    pub(crate) fn nested(
        &mut self,
        f: impl FnOnce(&mut Self) -> Result<Value, ModelError>,
    ) -> Result<Value, ModelError> {
        self.x.nest_in(self.at, "expressions")?;
        let r = f(self);
        self.x.leave();
        r
    }

    /// Runs `f` without evaluating (see [`Parser::skip`]).
    pub(crate) fn skipping(
        &mut self,
        f: impl FnOnce(&mut Self) -> Result<Value, ModelError>,
    ) -> Result<Value, ModelError> {
        self.skip += 1;
        let r = f(self);
        self.skip -= 1;
        r.map(|_| SKIPPED)
    }

    /// Python's truth of a value inside an expression: a non-empty string is true.
    pub(crate) fn truthy(&self, v: &Value) -> bool {
        match v {
            Value::Bool(b) => *b,
            Value::Int(i) => *i != 0,
            Value::Float(x) => *x != 0.0,
            Value::Str(s) => !s.is_empty(),
        }
    }

    /// `v if c else other`: as Python, only the branch chosen is evaluated (the value side is
    /// parsed first here, so an error in it counts only when it is chosen).
    pub(crate) fn ternary(&mut self) -> Result<Value, ModelError> {
        self.nested(|p| {
            let start = p.pos;
            let v = match p.or() {
                Ok(v) => Ok(v),
                Err(e) if p.skip == 0 => {
                    // Find where the value ends, then decide whether its error matters.
                    p.pos = start;
                    p.skipping(Self::or)?;
                    Err(e)
                }
                Err(e) => return Err(e),
            };
            if !p.eat_name("if") {
                return v;
            }
            if p.skip > 0 {
                p.or()?;
                if !p.eat_name("else") {
                    return Err(p.err("'if' without 'else'"));
                }
                p.ternary()?;
                return Ok(SKIPPED);
            }
            let c = p.or()?;
            if !p.eat_name("else") {
                return Err(p.err("'if' without 'else'"));
            }
            if p.truthy(&c) {
                p.skipping(Self::ternary)?;
                v
            } else {
                p.ternary()
            }
        })
    }

    pub(crate) fn or(&mut self) -> Result<Value, ModelError> {
        let mut v = self.and()?;
        while self.eat_name("or") {
            if self.skip > 0 || self.truthy(&v) {
                self.skipping(Self::and)?;
            } else {
                v = self.and()?;
            }
        }
        Ok(v)
    }

    pub(crate) fn and(&mut self) -> Result<Value, ModelError> {
        let mut v = self.not()?;
        while self.eat_name("and") {
            if self.skip > 0 || !self.truthy(&v) {
                self.skipping(Self::not)?;
            } else {
                v = self.not()?;
            }
        }
        Ok(v)
    }

    pub(crate) fn not(&mut self) -> Result<Value, ModelError> {
        if self.eat_name("not") {
            let v = self.nested(Self::not)?;
            return Ok(Value::Bool(!self.truthy(&v)));
        }
        self.cmp()
    }

    pub(crate) fn cmp(&mut self) -> Result<Value, ModelError> {
        let l = self.add()?;
        for op in ["==", "!=", "<=", ">=", "<", ">"] {
            if self.eat_op(op) {
                let r = self.add()?;
                if self.skip > 0 {
                    return Ok(SKIPPED);
                }
                // Numbers compare as numbers, anything with a string as text (NaN: unordered).
                let ord = match (l.num(), r.num()) {
                    (Some(a), Some(b))
                        if !matches!((&l, &r), (Value::Str(_), _) | (_, Value::Str(_))) =>
                    {
                        a.partial_cmp(&b)
                    }
                    _ => Some(l.to_text().cmp(&r.to_text())),
                };
                use std::cmp::Ordering::{Equal, Greater, Less};
                let b = match (op, ord) {
                    ("==", o) => o == Some(Equal),
                    ("!=", o) => o != Some(Equal),
                    ("<=", o) => matches!(o, Some(Less | Equal)),
                    (">=", o) => matches!(o, Some(Greater | Equal)),
                    ("<", o) => o == Some(Less),
                    (_, o) => o == Some(Greater),
                };
                return Ok(Value::Bool(b));
            }
        }
        Ok(l)
    }

    pub(crate) fn add(&mut self) -> Result<Value, ModelError> {
        let mut v = self.mul()?;
        loop {
            if self.eat_op("+") {
                let r = self.mul()?;
                v = match (&v, &r) {
                    _ if self.skip > 0 => SKIPPED,
                    (Value::Str(a), Value::Str(b)) => {
                        if a.len() + b.len() > MAX_OUTPUT_BYTES {
                            return Err(self.err(format!(
                                "a string longer than {} MiB",
                                MAX_OUTPUT_BYTES >> 20
                            )));
                        }
                        Value::Str(format!("{a}{b}"))
                    }
                    _ => self.arith(&v, &r, "+")?,
                };
            } else if self.eat_op("-") {
                let r = self.mul()?;
                v = self.arith(&v, &r, "-")?;
            } else {
                return Ok(v);
            }
        }
    }

    pub(crate) fn mul(&mut self) -> Result<Value, ModelError> {
        let mut v = self.unary()?;
        loop {
            let op = ["*", "//", "/", "%"].into_iter().find(|op| self.eat_op(op));
            match op {
                Some(op) => {
                    let r = self.unary()?;
                    v = self.arith(&v, &r, op)?;
                }
                None => return Ok(v),
            }
        }
    }

    pub(crate) fn unary(&mut self) -> Result<Value, ModelError> {
        if self.eat_op("-") {
            let v = self.nested(Self::unary)?;
            return match v {
                _ if self.skip > 0 => Ok(SKIPPED),
                Value::Int(i) => i
                    .checked_neg()
                    .map(Value::Int)
                    .ok_or_else(|| self.overflow()),
                other => Ok(Value::Float(
                    -other.num().ok_or_else(|| self.err("'-' on a string"))?,
                )),
            };
        }
        if self.eat_op("+") {
            return self.nested(Self::unary);
        }
        self.power()
    }

    pub(crate) fn power(&mut self) -> Result<Value, ModelError> {
        let base = self.postfix()?;
        if self.eat_op("**") {
            let e = self.nested(Self::unary)?;
            return self.arith(&base, &e, "**");
        }
        Ok(base)
    }

    /// An integer result beyond 64 bits: Python's integers have no bound, ours do.
    pub(crate) fn overflow(&self) -> ModelError {
        self.err("integer result beyond 64 bits (Python's unbounded integers are not supported)")
    }

    pub(crate) fn arith(&self, a: &Value, b: &Value, op: &str) -> Result<Value, ModelError> {
        if self.skip > 0 {
            return Ok(SKIPPED);
        }
        if let (Value::Int(x), Value::Int(y)) = (a, b) {
            let (x, y) = (*x, *y);
            // None: not an integer operation (division by zero, a negative power), handled
            // below as Python does; Some(None): the integer result overflows.
            let r: Option<Option<i64>> = match op {
                "+" => Some(x.checked_add(y)),
                "-" => Some(x.checked_sub(y)),
                "*" => Some(x.checked_mul(y)),
                "//" if y != 0 => Some(if y == -1 {
                    x.checked_neg()
                } else {
                    let q = x / y;
                    Some(if x % y != 0 && ((x < 0) != (y < 0)) {
                        q - 1
                    } else {
                        q
                    })
                }),
                "%" if y != 0 => Some(if y == -1 {
                    Some(0)
                } else {
                    let r = x % y;
                    Some(if r != 0 && ((r < 0) != (y < 0)) {
                        r + y
                    } else {
                        r
                    })
                }),
                "**" if y >= 0 => Some(match x {
                    0 | 1 => Some(if y == 0 { 1 } else { x }),
                    -1 => Some(if y % 2 == 0 { 1 } else { -1 }),
                    _ => u32::try_from(y).ok().and_then(|y| x.checked_pow(y)),
                }),
                _ => None,
            };
            match r {
                Some(Some(r)) => return Ok(Value::Int(r)),
                Some(None) => return Err(self.overflow()),
                None => {}
            }
        }
        let (x, y) = match (a.num(), b.num()) {
            (Some(x), Some(y)) if !matches!(a, Value::Str(_)) && !matches!(b, Value::Str(_)) => {
                (x, y)
            }
            _ => {
                return Err(self.err(format!(
                    "cannot apply '{op}' to {} and {}",
                    a.to_text(),
                    b.to_text()
                )))
            }
        };
        if (op == "/" || op == "//" || op == "%") && y == 0.0 {
            return Err(self.err("division by zero"));
        }
        Ok(Value::Float(match op {
            "+" => x + y,
            "-" => x - y,
            "*" => x * y,
            "/" => x / y,
            "//" => (x / y).floor(),
            "%" => x - y * (x / y).floor(),
            _ => x.powf(y),
        }))
    }

    pub(crate) fn postfix(&mut self) -> Result<Value, ModelError> {
        let tok = self
            .tokens
            .get(self.pos)
            .cloned()
            .ok_or_else(|| self.err("unexpected end"))?;
        self.pos += 1;
        match tok {
            Tok::Num(v) => Ok(v),
            Tok::Str(s) => Ok(Value::Str(s)),
            Tok::Op("(") => {
                let v = self.ternary()?;
                if !self.eat_op(")") {
                    return Err(self.err("missing ')'"));
                }
                Ok(v)
            }
            Tok::Name(mut name) => {
                if name == "math" && self.eat_op(".") {
                    match self.tokens.get(self.pos).cloned() {
                        Some(Tok::Name(f)) => {
                            self.pos += 1;
                            name = f;
                        }
                        _ => return Err(self.err("'math.' without a name")),
                    }
                }
                if self.eat_op("(") {
                    let mut args = Vec::new();
                    if !self.eat_op(")") {
                        loop {
                            args.push(self.ternary()?);
                            if self.eat_op(")") {
                                break;
                            }
                            if !self.eat_op(",") {
                                return Err(self.err(format!("{name}(…): expected ',' or ')'")));
                            }
                        }
                    }
                    if self.skip > 0 {
                        return Ok(SKIPPED);
                    }
                    return self.call(&name, &args);
                }
                if self.skip > 0 {
                    return Ok(SKIPPED);
                }
                match name.as_str() {
                    "pi" => Ok(Value::Float(std::f64::consts::PI)),
                    "e" if self.scope.prop("e").is_none() => Ok(Value::Float(std::f64::consts::E)),
                    "inf" => Ok(Value::Float(f64::INFINITY)),
                    "nan" => Ok(Value::Float(f64::NAN)),
                    "True" | "true" => Ok(Value::Bool(true)),
                    "False" | "false" => Ok(Value::Bool(false)),
                    _ => self.x.lookup(&name, self.scope, self.at),
                }
            }
            Tok::Op(o) => Err(self.err(format!("unexpected '{o}'"))),
        }
    }

    /// A float as a Python int (`int()`, `math.floor`, `round`): NaN, ±inf and values beyond
    /// 64 bits are errors, as Python's are (or would need unbounded integers).
    pub(crate) fn to_int(&self, f: &str, x: f64) -> Result<Value, ModelError> {
        if x.is_nan() {
            return Err(self.err(format!("{f}(): cannot convert NaN to an integer")));
        }
        if x.is_infinite() {
            return Err(self.err(format!("{f}(): cannot convert infinity to an integer")));
        }
        if x.abs() >= 2f64.powi(63) {
            return Err(self.overflow());
        }
        Ok(Value::Int(x as i64))
    }

    pub(crate) fn call(&self, f: &str, args: &[Value]) -> Result<Value, ModelError> {
        let nums = || -> Result<Vec<f64>, ModelError> {
            args.iter()
                .map(|a| {
                    a.num().ok_or_else(|| {
                        self.err(format!("{f}(): \"{}\" is not a number", a.to_text()))
                    })
                })
                .collect()
        };
        let one = |g: fn(f64) -> f64| -> Result<Value, ModelError> {
            match nums()?.as_slice() {
                [x] => Ok(Value::Float(g(*x))),
                _ => Err(self.err(format!("{f}() takes one argument"))),
            }
        };
        let one_num = || -> Result<f64, ModelError> {
            match nums()?.as_slice() {
                [x] => Ok(*x),
                _ => Err(self.err(format!("{f}() takes one argument"))),
            }
        };
        match f {
            "radians" => one(f64::to_radians),
            "degrees" => one(f64::to_degrees),
            "sin" => one(f64::sin),
            "cos" => one(f64::cos),
            "tan" => one(f64::tan),
            "asin" => one(f64::asin),
            "acos" => one(f64::acos),
            "atan" => one(f64::atan),
            "sinh" => one(f64::sinh),
            "cosh" => one(f64::cosh),
            "tanh" => one(f64::tanh),
            "sqrt" => one(f64::sqrt),
            "exp" => one(f64::exp),
            "log10" => one(f64::log10),
            "fabs" => one(f64::abs),
            "floor" => match args {
                [Value::Int(i)] => Ok(Value::Int(*i)),
                _ => self.to_int(f, one_num()?.floor()),
            },
            "ceil" => match args {
                [Value::Int(i)] => Ok(Value::Int(*i)),
                _ => self.to_int(f, one_num()?.ceil()),
            },
            "log" => match nums()?.as_slice() {
                [x] => Ok(Value::Float(x.ln())),
                [x, b] => Ok(Value::Float(x.ln() / b.ln())),
                _ => Err(self.err("log() takes one or two arguments")),
            },
            "atan2" | "pow" | "hypot" | "copysign" | "fmod" => match nums()?.as_slice() {
                [y, x] => Ok(Value::Float(match f {
                    "atan2" => y.atan2(*x),
                    "pow" => y.powf(*x),
                    "hypot" => y.hypot(*x),
                    "copysign" => y.copysign(*x),
                    _ => y % x,
                })),
                _ => Err(self.err(format!("{f}() takes two arguments"))),
            },
            "abs" => match args {
                [Value::Int(i)] => i
                    .checked_abs()
                    .map(Value::Int)
                    .ok_or_else(|| self.overflow()),
                _ => one(f64::abs),
            },
            "min" | "max" => {
                let v = nums()?;
                if v.is_empty() {
                    return Err(self.err(format!("{f}() needs arguments")));
                }
                let pick = if f == "min" {
                    v.iter().cloned().fold(f64::INFINITY, f64::min)
                } else {
                    v.iter().cloned().fold(f64::NEG_INFINITY, f64::max)
                };
                let i = v.iter().position(|x| *x == pick).unwrap_or(0);
                Ok(args[i].clone())
            }
            "float" => match args {
                [Value::Str(s)] => python_float(s)
                    .map(Value::Float)
                    .ok_or_else(|| self.err(format!("float(\"{s}\"): not a number"))),
                _ => one(|x| x),
            },
            "int" => match args {
                [Value::Str(s)] => s.trim().parse::<i64>().map(Value::Int).map_err(|_| {
                    self.err(format!("int(\"{s}\"): not an integer (or beyond 64 bits)"))
                }),
                [Value::Int(i)] => Ok(Value::Int(*i)),
                _ => self.to_int(f, one_num()?.trunc()),
            },
            "round" => match args {
                [Value::Int(i)] => Ok(Value::Int(*i)),
                [Value::Int(i), Value::Int(n)] if *n >= 0 => Ok(Value::Int(*i)),
                [Value::Int(i), Value::Int(n)] => {
                    // Python: an int rounded to 10^-n, halves to even.
                    let p = 10i64.checked_pow(u32::try_from(-*n).unwrap_or(u32::MAX));
                    match p {
                        None => Ok(Value::Int(0)),
                        Some(p) => {
                            let r = round_half_even(*i as f64 / p as f64) as i64;
                            r.checked_mul(p)
                                .map(Value::Int)
                                .ok_or_else(|| self.overflow())
                        }
                    }
                }
                [_] => self.to_int(f, round_half_even(one_num()?)),
                [x, Value::Int(n)] => {
                    let x = x.num().ok_or_else(|| self.err("round(): not a number"))?;
                    Ok(Value::Float(python_round(x, *n)))
                }
                [_, _] => Err(self.err("round(): the number of digits must be an integer")),
                _ => Err(self.err("round() takes one or two arguments")),
            },
            "str" => match args {
                [v] => Ok(Value::Str(v.to_text())),
                _ => Err(self.err("str() takes one argument")),
            },
            "bool" => match args {
                [v] => Ok(Value::Bool(self.truthy(v))),
                _ => Err(self.err("bool() takes one argument")),
            },
            _ => Err(self.err(format!("unknown function {f}()"))),
        }
    }
}
