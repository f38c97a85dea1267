//! The names of a measurement's choices, as the CLI's options and the Python package's
//! arguments give them: [`PlanOrder`] (`optimized`, `nested`) and [`HdrChoice`]
//! (`predicted`, `bracket`). Their [`std::fmt::Display`] writes the same names.

use crate::journal::{HdrChoice, PlanOrder};
use specula_core::request::{parse_choice, ChoiceError};
use std::str::FromStr;

impl FromStr for PlanOrder {
    type Err = ChoiceError;

    /// `optimized` or `nested`.
    fn from_str(text: &str) -> Result<Self, ChoiceError> {
        parse_choice(
            "order",
            text,
            &[PlanOrder::Optimized, PlanOrder::Nested],
            &["optimized", "nested"],
            |order| match order {
                PlanOrder::Optimized => "optimized",
                PlanOrder::Nested => "nested",
            },
        )
    }
}

impl FromStr for HdrChoice {
    type Err = ChoiceError;

    /// `predicted` or `bracket`.
    fn from_str(text: &str) -> Result<Self, ChoiceError> {
        parse_choice(
            "hdr",
            text,
            &[HdrChoice::Predicted, HdrChoice::Bracket],
            &["predicted", "bracket"],
            |hdr| match hdr {
                HdrChoice::Predicted => "predicted",
                HdrChoice::Bracket => "bracket",
            },
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_round_trip_and_a_wrong_one_lists_them() {
        for order in [PlanOrder::Optimized, PlanOrder::Nested] {
            assert_eq!(order.to_string().parse::<PlanOrder>(), Ok(order));
        }
        for hdr in [HdrChoice::Predicted, HdrChoice::Bracket] {
            assert_eq!(hdr.to_string().parse::<HdrChoice>(), Ok(hdr));
        }
        assert_eq!(
            "fast".parse::<PlanOrder>().unwrap_err().to_string(),
            "order 'fast': expected one of optimized, nested"
        );
        assert_eq!(
            "auto".parse::<HdrChoice>().unwrap_err().to_string(),
            "hdr 'auto': expected one of predicted, bracket"
        );
    }
}
