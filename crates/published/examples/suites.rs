//! Prints the generated part of `docs/suites.md`: every named suite's family, source, material
//! count, the materials outside the family's bounds (and whether they are included), and the
//! materials (`brdf_published::suite::listing_markdown`, green channel).
//!
//! ```sh
//! cargo run -p brdf-published --example suites
//! ```

fn main() {
    match brdf_published::suite::listing_markdown(brdf_io::Channel::Green) {
        Ok(text) => print!("{text}"),
        Err(e) => {
            eprintln!("error: {e}");
            std::process::exit(1);
        }
    }
}
