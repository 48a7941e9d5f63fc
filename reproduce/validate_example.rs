//! The example external engine of VALIDATION.md: the reference engine behind
//! the external-program contract. `validate --candidate cmd:'PATH/validate-example'`
//! must pass; an engine in another language does what this does.
//!
//! Protocol: called as `validate-example run --plan -`, it reads one JSON
//! RunPlan on stdin and prints one JSON Sample per line on stdout.

use granular_automata::pipe::engine::Reference;
use granular_automata::validate::candidate::serve;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    if args != ["run", "--plan", "-"] {
        return Err(format!(
            "usage: validate-example run --plan - (a RunPlan as JSON on stdin); got {args:?}"
        )
        .into());
    }
    let stdout = std::io::stdout();
    let mut out = std::io::BufWriter::new(stdout.lock());
    serve(Reference, &mut std::io::stdin(), &mut out)?;
    Ok(())
}
