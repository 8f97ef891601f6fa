//! Errors as the app sees them: `{code, message, hint}`. Core errors convert through one
//! function, [`ui_error`], from their [`Explain`] code and hint and their message; the facade's
//! own argument checks (an unknown name, a bad axis) build a [`UiError`] directly.

use crate::error::Explain;
use serde::Serialize;
use std::fmt::Display;
use wasm_bindgen::JsValue;

/// An error as the UI sees it: a stable machine code, a sentence, and what to try.
#[derive(Serialize, Debug, Clone, PartialEq, tsify::Tsify)]
pub struct UiError {
    /// Stable identifier, one of [`crate::error::CODES`] (e.g. `bad-parameter`, `solve-failed`).
    pub code: &'static str,
    /// What went wrong, naming the problem.
    pub message: String,
    /// What the user can do about it.
    pub hint: String,
}

impl UiError {
    /// A `bad-parameter` error: an argument from the page out of its range or list.
    pub fn bad_parameter(message: String, hint: impl Into<String>) -> UiError {
        UiError {
            code: "bad-parameter",
            message,
            hint: hint.into(),
        }
    }

    /// A name not in its list: `{what} "{name}"` and the hint "Use a, b or c.".
    pub fn unknown(what: &str, name: &str, names: &[&str]) -> UiError {
        UiError::bad_parameter(
            format!("{what} \"{name}\""),
            format!("Use {}.", crate::io::formats::join_list(names, "or")),
        )
    }

    /// Unreadable settings JSON (from the page's advanced settings or a share link).
    pub fn settings(e: impl Display) -> UiError {
        UiError::bad_parameter(format!("settings: {e}"), crate::error::SETTINGS_HINT)
    }
}

/// Any core error as the app's `{code, message, hint}` object.
pub fn ui_error<E: Explain + Display>(e: E) -> JsValue {
    UiError {
        code: e.code(),
        message: e.to_string(),
        hint: e.hint().to_owned(),
    }
    .into()
}

impl From<UiError> for JsValue {
    fn from(e: UiError) -> JsValue {
        serde_wasm_bindgen::to_value(&e).unwrap_or_else(|_| JsValue::from_str(&e.message))
    }
}
