//! The lexer of `${…}` expressions: numbers, strings, names, operators.

use super::*;

#[derive(Debug, Clone, PartialEq)]
pub(crate) enum Tok {
    Num(Value),
    Str(String),
    Name(String),
    Op(&'static str),
}

pub(crate) fn lex(s: &str) -> Result<Vec<Tok>, String> {
    const OPS: [&str; 22] = [
        "**", "//", "==", "!=", "<=", ">=", "+", "-", "*", "/", "%", "<", ">", "(", ")", ",", ".",
        "[", "]", "{", "}", ":",
    ];
    let mut out = Vec::new();
    let cs: Vec<char> = s.chars().collect();
    let mut i = 0;
    while i < cs.len() {
        let c = cs[i];
        if c.is_whitespace() {
            i += 1;
        } else if c.is_ascii_digit()
            || (c == '.' && cs.get(i + 1).is_some_and(|d| d.is_ascii_digit()))
        {
            let start = i;
            while i < cs.len()
                && (cs[i].is_ascii_alphanumeric()
                    || cs[i] == '.'
                    || ((cs[i] == '+' || cs[i] == '-') && matches!(cs[i - 1], 'e' | 'E')))
            {
                i += 1;
            }
            let t: String = cs[start..i].iter().collect();
            let v = match t.parse::<i64>() {
                Ok(n) => Value::Int(n),
                Err(_) if t.chars().all(|c| c.is_ascii_digit()) => {
                    return Err(format!("integer {t} is beyond 64 bits (Python's unbounded integers are not supported)"));
                }
                Err(_) => Value::Float(
                    t.parse::<f64>()
                        .ok()
                        .filter(|_| !t.contains(['i', 'I', 'n', 'N']))
                        .ok_or_else(|| format!("bad number \"{t}\""))?,
                ),
            };
            out.push(Tok::Num(v));
        } else if c.is_alphabetic() || c == '_' {
            let start = i;
            while i < cs.len() && (cs[i].is_alphanumeric() || cs[i] == '_') {
                i += 1;
            }
            out.push(Tok::Name(cs[start..i].iter().collect()));
        } else if c == '\'' || c == '"' {
            let start = i + 1;
            i += 1;
            while i < cs.len() && cs[i] != c {
                i += 1;
            }
            if i == cs.len() {
                return Err("unclosed string".into());
            }
            out.push(Tok::Str(cs[start..i].iter().collect()));
            i += 1;
        } else {
            let rest: String = cs[i..cs.len().min(i + 2)].iter().collect();
            let op = OPS
                .iter()
                .find(|o| rest.starts_with(**o))
                .ok_or_else(|| format!("unexpected character '{c}'"))?;
            out.push(Tok::Op(op));
            i += op.chars().count();
        }
    }
    Ok(out)
}
