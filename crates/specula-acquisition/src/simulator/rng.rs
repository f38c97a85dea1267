//! Deterministic random streams for the simulator.
//!
//! Every random draw of the simulator comes from a stream keyed by what identifies it (the
//! seed, the mounted target, the commanded axis angles, the exposure, the light level, the
//! repeat count at that position), never from one sequential generator. So a capture is the
//! same whatever was captured before it, in any order and after a restart.

use rand_chacha::rand_core::SeedableRng;
use rand_chacha::ChaCha8Rng;

/// One step of SplitMix64 (Steele, Lea and Flood 2014): a bijective 64-bit mixer.
fn splitmix64(mut z: u64) -> u64 {
    z = z.wrapping_add(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// A 64-bit key from a sequence of words; stable across runs, platforms and Rust versions.
pub fn key(words: &[u64]) -> u64 {
    words
        .iter()
        .fold(0x5EC0_1A5E_ED00_0001, |h, &w| splitmix64(h ^ splitmix64(w)))
}

/// A random stream for the given key words.
pub fn stream(words: &[u64]) -> ChaCha8Rng {
    ChaCha8Rng::seed_from_u64(key(words))
}

/// A real number as a key word, rounded to a multiple of `quantum` so that values equal up to
/// floating-point noise give the same word.
pub fn quantised(value: f64, quantum: f64) -> u64 {
    (value / quantum).round() as i64 as u64
}

/// A text (a target's name) as a key word.
pub fn text(value: &str) -> u64 {
    key(&value.bytes().map(u64::from).collect::<Vec<_>>())
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::Rng;

    #[test]
    fn streams_depend_on_every_word_and_on_nothing_else() {
        let a: u64 = stream(&[1, 2, 3]).random();
        let b: u64 = stream(&[1, 2, 3]).random();
        let c: u64 = stream(&[1, 2, 4]).random();
        let d: u64 = stream(&[2, 1, 3]).random();
        assert_eq!(a, b);
        assert_ne!(a, c);
        assert_ne!(a, d, "order of the words matters");
    }

    #[test]
    fn quantisation_absorbs_rounding_noise() {
        let x = 0.1 + 0.2;
        assert_eq!(quantised(x, 1e-9), quantised(0.3, 1e-9));
        assert_ne!(quantised(0.3, 1e-9), quantised(0.3 + 2e-9, 1e-9));
        assert_ne!(quantised(-0.3, 1e-9), quantised(0.3, 1e-9));
        assert_ne!(text("white"), text("whitf"));
    }
}
