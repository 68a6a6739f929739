//! Scopes: properties (lazy, evaluated on first use), macros and their parameters, looked up
//! through the callers as xacro does (`Rc<RefCell<Frame>>` per scope).

use super::*;

#[derive(Debug, Clone)]
pub(super) enum Prop {
    /// Text not yet evaluated (xacro evaluates properties when they are used), with the scope
    /// it was defined in.
    Lazy(String, Scope, At),
    Value(Value),
    Block(Vec<Node>),
}

#[derive(Debug, Clone)]
pub(super) struct Macro {
    pub(super) params: Vec<Param>,
    pub(super) body: Vec<Node>,
}

#[derive(Debug, Clone)]
pub(super) struct Param {
    pub(super) name: String,
    /// 0: a value, 1: `*block` (one element), 2: `**block` (an element's children).
    pub(super) stars: usize,
    pub(super) default: Option<String>,
    /// `^`: taken from the caller's scope when not given.
    pub(super) inherit: bool,
}

#[derive(Debug, Default)]
pub(super) struct Frame {
    pub(super) parent: Option<Scope>,
    pub(super) props: HashMap<String, Prop>,
    pub(super) macros: HashMap<String, Rc<Macro>>,
    /// Properties being evaluated (cycle detection).
    pub(super) busy: Vec<String>,
}

#[derive(Debug, Clone)]
pub(super) struct Scope(pub(super) Rc<RefCell<Frame>>);

impl Scope {
    pub(super) fn new(parent: Option<Scope>) -> Self {
        Scope(Rc::new(RefCell::new(Frame {
            parent,
            ..Frame::default()
        })))
    }

    pub(super) fn prop(&self, name: &str) -> Option<(Prop, Scope)> {
        let f = self.0.borrow();
        match f.props.get(name) {
            Some(p) => Some((p.clone(), self.clone())),
            None => f.parent.as_ref().and_then(|p| p.prop(name)),
        }
    }

    pub(super) fn macro_(&self, name: &str) -> Option<Rc<Macro>> {
        let f = self.0.borrow();
        match f.macros.get(name) {
            Some(m) => Some(m.clone()),
            None => f.parent.as_ref().and_then(|p| p.macro_(name)),
        }
    }

    pub(super) fn parent_or_self(&self) -> Scope {
        self.0
            .borrow()
            .parent
            .clone()
            .unwrap_or_else(|| self.clone())
    }

    pub(super) fn global(&self) -> Scope {
        match &self.0.borrow().parent {
            Some(p) => p.global(),
            None => self.clone(),
        }
    }
}
