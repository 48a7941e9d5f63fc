use granular_automata::pipe::open::open_run;
use granular_automata::pipe::{Boundary, Params, Rules};
fn main() {
    for &(l, w) in &[(1000usize, 5usize), (220, 11)] {
        for &i in &[0.02, 0.05, 0.1, 0.2, 0.3, 0.5] {
            let params = Params {
                length: l,
                width: w,
                p: 0.5,
                b: 0.5,
                g: std::env::args()
                    .nth(1)
                    .map(|s| s.parse().unwrap())
                    .unwrap_or(0.2),
                boundary: Boundary::Open { inject: i },
                ..Params::default()
            };
            match open_run(params, Rules::default(), 1, 40000, 1000, false, &|_| {}) {
                Ok(r) => println!(
                    "L{l} W{w} I={i}: N(t) every 4000: {:?} out_bottom {}",
                    r.total.iter().step_by(4).collect::<Vec<_>>(),
                    r.out_bottom
                ),
                Err(e) => println!("L{l} W{w} I={i}: {e}"),
            }
        }
    }
}
