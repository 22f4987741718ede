//! The named fields of a DP slave's images for `edsgen dp io`: every module of its
//! configuration in slot order, each as 16-bit words (`w0`, `w1`, ...; a module whose
//! identifiers are all words) or bytes (`b0`, ...), a PKW/PZD module (the overlay's `[pkw_pzd]`)
//! as `pkw1`-`pkw4`, `cw`/`sw`, `pzd2`-`pzd12`. With several modules each name starts with its
//! slot: `slot2.b0`. Settings by name, and the text of what changed.

use edsgen_model::model::modules::DpConfiguration;
use edsgen_model::model::Dp;

const PKW_PZD_NAMES: [&str; 16] = [
    "pkw1", "pkw2", "pkw3", "pkw4", "cw", "pzd2", "pzd3", "pzd4", "pzd5", "pzd6", "pzd7", "pzd8",
    "pzd9", "pzd10", "pzd11", "pzd12",
];

/// One named word or byte of an image.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Field {
    /// Its name.
    pub name: String,
    /// Its first byte in the image.
    pub offset: usize,
    /// 2 for a big-endian word, 1 for a byte.
    pub width: usize,
}

impl Field {
    /// The field's value in `image` and its text.
    fn text(&self, image: &[u8]) -> String {
        let at = self.offset;
        if self.width == 2 {
            let word = u16::from_be_bytes([image[at], image[at + 1]]);
            format!("{word} (0x{word:04X})")
        } else {
            format!("{} (0x{:02X})", image[at], image[at])
        }
    }
}

/// The fields of a configuration's images, and where its PKW/PZD module is.
#[derive(Debug, Clone, Default)]
pub struct Layout {
    /// The input image's fields (slave to master), in order.
    pub inputs: Vec<Field>,
    /// The output image's fields (master to slave), in order.
    pub outputs: Vec<Field>,
    /// The PKW/PZD module's 32-byte images: their offsets in the inputs and the outputs.
    pub pkw_pzd: Option<(usize, usize)>,
}

impl Layout {
    /// The layout of `configuration`'s images.
    pub fn new(dp: &Dp, configuration: &DpConfiguration) -> Layout {
        let mut layout = Layout::default();
        let several = configuration.slots.len() > 1;
        let (mut input_at, mut output_at) = (0, 0);
        for (slot, module) in configuration.modules(dp) {
            let prefix = if several {
                format!("slot{slot}.")
            } else {
                String::new()
            };
            // Identifiers that carry data (an empty slot's 00h says nothing of words).
            let ids: Vec<_> = module
                .identifiers()
                .into_iter()
                .filter(|i| i.input_bytes + i.output_bytes > 0)
                .collect();
            let (input_len, output_len) = module.io_lengths();
            let (input_len, output_len) = (input_len as usize, output_len as usize);
            let pkw_pzd = dp.pkw_pzd_module.as_deref() == Some(module.name.as_str());
            let words = pkw_pzd
                || (!ids.is_empty()
                    && ids.iter().all(|i| i.words)
                    && input_len % 2 == 0
                    && output_len % 2 == 0);
            let width = if words { 2 } else { 1 };
            let name = |n: usize, input: bool| -> String {
                match n {
                    4 if pkw_pzd && input => format!("{prefix}sw"),
                    n if pkw_pzd && n < 16 => format!("{prefix}{}", PKW_PZD_NAMES[n]),
                    n if words => format!("{prefix}w{n}"),
                    n => format!("{prefix}b{n}"),
                }
            };
            for (fields, at, len, input) in [
                (&mut layout.inputs, input_at, input_len, true),
                (&mut layout.outputs, output_at, output_len, false),
            ] {
                fields.extend((0..len / width).map(|n| Field {
                    name: name(n, input),
                    offset: at + n * width,
                    width,
                }));
            }
            if pkw_pzd && layout.pkw_pzd.is_none() {
                layout.pkw_pzd = Some((input_at, output_at));
            }
            input_at += input_len;
            output_at += output_len;
        }
        layout
    }

    /// Applies one setting to `outputs`: `NAME=VALUE` (decimal or 0x hex), or `reset`, `run`,
    /// `stop` on a PKW/PZD module (CW commands 7, 1, 5).
    pub fn apply(&self, setting: &str, outputs: &mut [u8]) -> Result<(), String> {
        let setting = setting.trim();
        // The card's control word commands (CW bits 0-7): 1 run forward, 5 stop, 7 fault reset.
        let command = match setting {
            "run" => Some(1),
            "stop" => Some(5),
            "reset" => Some(7),
            _ => None,
        };
        if let Some(command) = command {
            let Some((_, at)) = self.pkw_pzd else {
                return Err(format!(
                    "`{setting}`: the module has no PKW/PZD control word"
                ));
            };
            outputs[at + 9] = command;
            return Ok(());
        }
        let Some((name, value)) = setting.split_once('=') else {
            return Err(format!("`{setting}` is not NAME=VALUE, reset, run or stop"));
        };
        let wanted = name.trim().to_ascii_lowercase();
        let field = self.outputs.iter().find(|f| f.name == wanted);
        let Some(field) = field else {
            return Err(format!(
                "`{setting}`: no output `{}`{}",
                name.trim(),
                self.known()
            ));
        };
        let value = number(value.trim()).filter(|v| field.width == 2 || *v <= 0xFF);
        let Some(value) = value else {
            let kind = if field.width == 2 {
                "a 16-bit"
            } else {
                "an 8-bit"
            };
            return Err(format!("`{setting}`: not {kind} value"));
        };
        let at = field.offset;
        if field.width == 2 {
            outputs[at..at + 2].copy_from_slice(&value.to_be_bytes());
        } else {
            outputs[at] = value as u8;
        }
        Ok(())
    }

    /// ` (the outputs are A, B, ... Z)`, or ` (the slave has no outputs)`.
    fn known(&self) -> String {
        match (self.outputs.first(), self.outputs.last()) {
            (Some(first), Some(last)) if self.outputs.len() > 2 => {
                format!(" (the outputs are {}, ... {})", first.name, last.name)
            }
            (Some(_), _) => {
                let names: Vec<&str> = self.outputs.iter().map(|f| f.name.as_str()).collect();
                format!(" (the outputs are {})", names.join(", "))
            }
            _ => " (the slave has no outputs)".to_owned(),
        }
    }

    /// One `NAME = VALUE (HEX)` line per input field that differs from `before` (every one
    /// the first time).
    pub fn changes(&self, before: Option<&[u8]>, now: &[u8]) -> Vec<String> {
        self.inputs
            .iter()
            .filter(|f| changed(before, now, f.offset..f.offset + f.width))
            .map(|f| format!("{} = {}", f.name, f.text(now)))
            .collect()
    }
}

/// Whether the bytes `range` of `now` differ from `before`'s (always, without `before`).
pub fn changed(before: Option<&[u8]>, now: &[u8], range: std::ops::Range<usize>) -> bool {
    before.is_none_or(|b| b.get(range.clone()) != now.get(range))
}

/// A 16-bit number: decimal or `0x` hex.
fn number(text: &str) -> Option<u16> {
    match text.strip_prefix("0x").or_else(|| text.strip_prefix("0X")) {
        Some(hex) => u16::from_str_radix(hex, 16).ok(),
        None => text.parse().ok(),
    }
}
