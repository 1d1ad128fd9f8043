//! [`Session`]: what one interpreter remembers between evaluations on behalf
//! of its built-ins (e.g. the skeletons of the clips it loaded, so a motion
//! derived from a clip can still be written back to BVH). Each
//! [`super::Interpreter`] has its own; nothing in it is process-wide, so two
//! interpreters in one process never see each other's state.

use std::any::{Any, TypeId};
use std::sync::{Arc, Mutex};

/// One slot per type, created on first use.
#[derive(Default)]
pub struct Session {
    slots: Mutex<Vec<(TypeId, Arc<dyn Any + Send + Sync>)>>,
}

impl Session {
    pub fn new() -> Self {
        Self::default()
    }

    /// The slot of type `T`, made with `T::default()` the first time.
    pub fn get<T: Any + Send + Sync + Default>(&self) -> Arc<T> {
        let mut slots = self.slots.lock().unwrap_or_else(|p| p.into_inner());
        let id = TypeId::of::<T>();
        let slot = match slots.iter().find(|(t, _)| *t == id) {
            Some((_, s)) => s.clone(),
            None => {
                let s: Arc<dyn Any + Send + Sync> = Arc::new(T::default());
                slots.push((id, s.clone()));
                s
            }
        };
        // The slot was stored under T's TypeId, so it is a T.
        slot.downcast::<T>()
            .unwrap_or_else(|_| Arc::new(T::default()))
    }
}

impl std::fmt::Debug for Session {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("Session")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[derive(Default)]
    struct Counter(Mutex<u32>);

    #[test]
    fn a_slot_is_made_once_and_sessions_are_separate() {
        let a = Session::new();
        let b = Session::new();
        *a.get::<Counter>().0.lock().unwrap() += 1;
        *a.get::<Counter>().0.lock().unwrap() += 1;
        assert_eq!(*a.get::<Counter>().0.lock().unwrap(), 2);
        assert_eq!(*b.get::<Counter>().0.lock().unwrap(), 0);
    }
}
