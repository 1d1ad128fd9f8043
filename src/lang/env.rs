//! Immutable, persistent environments: a linked list of bindings shared by
//! `Arc`. Extending an environment never changes the one it extends, so a
//! closure can keep the environment it was made in while evaluation goes on,
//! and values stay `Send + Sync` (no `RefCell`).
//!
//! Generic over the bound value so this file needs nothing of `value.rs`,
//! where closures hold environments: mx's is `value::Env = Scope<Value>`.

use std::sync::Arc;

#[derive(Debug)]
struct Node<V> {
    name: String,
    value: V,
    next: Scope<V>,
}

/// Bindings of names to `V`s, innermost first.
#[derive(Debug)]
pub struct Scope<V>(Option<Arc<Node<V>>>);

impl<V> Clone for Scope<V> {
    fn clone(&self) -> Self {
        Scope(self.0.clone())
    }
}

impl<V> Default for Scope<V> {
    fn default() -> Self {
        Scope(None)
    }
}

impl<V> Scope<V> {
    pub fn empty() -> Self {
        Scope(None)
    }

    /// A new environment with `name` bound to `value` (shadowing older bindings).
    #[must_use]
    pub fn bind(&self, name: impl Into<String>, value: V) -> Self {
        Scope(Some(Arc::new(Node {
            name: name.into(),
            value,
            next: self.clone(),
        })))
    }

    pub fn get(&self, name: &str) -> Option<&V> {
        let mut cur = &self.0;
        while let Some(node) = cur {
            if node.name == name {
                return Some(&node.value);
            }
            cur = &node.next.0;
        }
        None
    }

    /// Every visible name, innermost first, without duplicates.
    pub fn names(&self) -> Vec<String> {
        let mut seen = std::collections::HashSet::new();
        let mut out = Vec::new();
        let mut cur = &self.0;
        while let Some(node) = cur {
            if seen.insert(node.name.as_str()) {
                out.push(node.name.clone());
            }
            cur = &node.next.0;
        }
        out
    }
}

impl<V> Drop for Scope<V> {
    // Dropping a long chain recursively could overflow the stack (a script
    // with 100,000 `let`s); unlink it iteratively instead.
    fn drop(&mut self) {
        let mut cur = self.0.take();
        while let Some(node) = cur {
            match Arc::try_unwrap(node) {
                Ok(mut n) => cur = n.next.0.take(),
                Err(_) => break,
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    type Env = Scope<f64>;

    #[test]
    fn binding_shadows_without_mutating() {
        let a = Env::empty().bind("x", 1.0);
        let b = a.bind("x", 2.0);
        assert_eq!(a.get("x"), Some(&1.0));
        assert_eq!(b.get("x"), Some(&2.0));
        assert!(b.get("y").is_none());
        assert_eq!(b.names(), vec!["x".to_string()]);
    }

    #[test]
    fn long_chains_drop_without_overflow() {
        let mut e = Env::empty();
        for i in 0..200_000 {
            e = e.bind(format!("v{i}"), 0.0);
        }
        drop(e);
    }
}
