//! Text for the notebooks' `_repr_html_`.

/// `s` safe inside HTML text and double-quoted attributes.
pub fn html_escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}
