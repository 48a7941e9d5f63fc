use granular_automata::pipe::{
    record::{bands, record},
    Params, Pipe, Rules,
};
fn main() {
    let args: Vec<String> = std::env::args().collect();
    let rules: Rules = args
        .get(1)
        .map(|s| s.as_str())
        .unwrap_or("default")
        .parse()
        .unwrap();
    let p: f64 = args.get(2).map(|s| s.parse().unwrap()).unwrap_or(0.1);
    let b: f64 = args.get(3).map(|s| s.parse().unwrap()).unwrap_or(0.5);
    let rho: f64 = args.get(4).map(|s| s.parse().unwrap()).unwrap_or(1.0);
    let l: usize = args.get(5).map(|s| s.parse().unwrap()).unwrap_or(2200);
    let steps: u64 = args.get(6).map(|s| s.parse().unwrap()).unwrap_or(40000);
    for seed in 1..=3 {
        let params = Params {
            length: l,
            width: 11,
            rho,
            p,
            g: 0.5,
            b,
            ..Params::default()
        };
        let mut pipe = Pipe::new(params, rules, seed).unwrap();
        let t = std::time::Instant::now();
        let rec = record(&mut pipe, steps, 80, |_| {}).unwrap();
        let bnd = bands(&rec, rec.n.len() / 2, rho, 10, 11);
        println!(
            "{rules} p={p} b={b} rho={rho} seed={seed}: C={:.3} s_low={:.2} channels={:?} {:.2}s",
            bnd.contrast,
            bnd.s_low,
            pipe.channel_counts(),
            t.elapsed().as_secs_f64()
        );
    }
}
