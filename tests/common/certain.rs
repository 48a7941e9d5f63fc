//! Draws for the reference pipe when only certain outcomes are compared
//! (the fast engine against the reference where no step has a choice).

use granular_automata::pipe::draws::Draws;
use std::cell::Cell;
use std::rc::Rc;

/// The reference's draws when only certain outcomes are expected: counts
/// every draw that had a real choice (and then takes the first branch).
#[derive(Clone, Default)]
pub struct Certain {
    /// Draws with a real choice so far (shared with clones).
    pub choices: Rc<Cell<u64>>,
    hops: Cell<u64>,
}

impl Certain {
    fn choice(&self) {
        self.choices.set(self.choices.get() + 1);
    }
}

impl Draws for Certain {
    fn uncertain(&mut self, _t: u64) -> bool {
        self.choice();
        false
    }
    fn pick(&mut self, _cumulative: &[u64]) -> usize {
        self.choice();
        0
    }
    fn coin(&mut self) -> bool {
        self.choice();
        false
    }
    fn below(&mut self, n: u32) -> u32 {
        if n > 1 {
            self.choice();
        }
        // a hash of a counter: a walk that always took the same neighbour
        // could go back and forth between two full sites until its bound
        let mut z = self.hops.get().wrapping_add(0x9E37_79B9_7F4A_7C15);
        self.hops.set(z);
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        ((z ^ (z >> 31)) % n as u64) as u32
    }
}
