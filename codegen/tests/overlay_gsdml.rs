//! `[pkw_pzd]` of a GSDML file's overlay (`eds/goodrive350-pn.toml`): the submodule it names
//! gets the conversions to and from `edsgen_runtime::pkw_pzd`'s images, and every refusal
//! (EDS708) has its exact line, column and message in the TOML text.

use std::path::Path;

use edsgen_codegen::emit;
use edsgen_model::diag::Severity;
use edsgen_model::model::Device;
use edsgen_model::{overlay, read, render};

fn card() -> String {
    std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("../eds/goodrive350-pn.xml"))
        .expect("eds/goodrive350-pn.xml")
}

fn device(text: &str) -> Device {
    read::read_bytes(Path::new("goodrive350-pn.xml"), text.as_bytes()).device
}

/// The card with `from` replaced by `to` (which must be there).
fn edited(from: &str, to: &str) -> String {
    let text = card();
    assert!(text.contains(from), "the card has no `{from}`");
    text.replacen(from, to, 1)
}

/// Which submodules (module or access point ID, subslot) are marked as PKW/PZD.
fn marked(device: &Device) -> Vec<(String, u16)> {
    let pn = device.profinet().expect("GSDML");
    let modules = pn.modules.iter().map(|m| (&m.id, &m.submodules));
    let daps = pn.access_points.iter().map(|d| (&d.id, &d.submodules));
    modules
        .chain(daps)
        .flat_map(|(id, subs)| {
            subs.iter()
                .filter(|s| s.pkw_pzd)
                .map(move |s| (id.clone(), s.subslot))
        })
        .collect()
}

/// (line, column, message) of each refusal of `toml` on the GSDML `text`, which are all EDS708
/// errors; and nothing is marked then.
fn refusals_on(text: &str, toml: &str) -> Vec<(u32, u32, String)> {
    let mut device = device(text);
    let diags = overlay::apply(toml, &mut device);
    assert_eq!(marked(&device), vec![], "a refused [pkw_pzd] marks nothing");
    diags
        .into_iter()
        .map(|d| {
            assert_eq!((d.code(), d.severity), ("EDS708", Severity::Error));
            let span = d.span.unwrap_or_else(|| panic!("no span: {}", d.message));
            (span.line, span.column, d.message)
        })
        .collect()
}

fn refusals(toml: &str) -> Vec<(u32, u32, String)> {
    refusals_on(&card(), toml)
}

#[test]
fn the_cards_overlay_marks_its_module_s_submodule() {
    let toml = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../eds/goodrive350-pn.toml"),
    )
    .expect("eds/goodrive350-pn.toml");
    let mut device = device(&card());
    assert_eq!(overlay::apply(&toml, &mut device), vec![]);
    assert_eq!(marked(&device), [("MOD_PKW_PZD_16".to_owned(), 1)]);
    let code = emit::generate(&device, "goodrive350_pn").expect("generates");
    // Compared without whitespace: the formatter breaks long signatures.
    let squeezed = code.split_whitespace().collect::<String>();
    let rt = "::edsgen_runtime::pkw_pzd::";
    for signature in [
        "implInput{".to_owned(),
        format!("pubfnpkw_pzd(&self,)->Result<{rt}InputImage,{rt}ResponseError,>{{"),
        format!("pubfnfrom_pkw_pzd(image:&{rt}InputImage,)->Self{{"),
        "implOutput{".to_owned(),
        format!("pubfnpkw_pzd(&self)->{rt}OutputImage{{"),
        format!("pubfnfrom_pkw_pzd(image:&{rt}OutputImage,)->Self{{"),
    ] {
        assert!(squeezed.contains(&signature), "{signature} in {code}");
    }
    assert!(squeezed.contains(&format!(
        "{rt}InputImage::parse(&self.to_bytes(),{rt}ByteOrder::BigEndian,)"
    )));
    // Without the overlay the images are the GSDML's alone.
    let plain = emit::generate(&self::device(&card()), "goodrive350_pn").expect("generates");
    assert!(!plain.contains("::edsgen_runtime::pkw_pzd"));
}

#[test]
fn a_module_is_named_by_id_or_by_name_and_one_submodule_needs_no_subslot() {
    let mut device = device(&card());
    assert_eq!(
        overlay::apply("[pkw_pzd]\nmodule = \"PKW PZD 16 words\"\n", &mut device),
        vec![]
    );
    assert_eq!(marked(&device), [("MOD_PKW_PZD_16".to_owned(), 1)]);
}

#[test]
fn unknown_module_and_subslot() {
    assert_eq!(
        refusals("[pkw_pzd]\nmodule = \"MOD_PKW\"\nsubslot = 1\n"),
        [(
            2,
            10,
            "no ModuleItem or DeviceAccessPointItem has the ID or name \"MOD_PKW\"".to_owned()
        )]
    );
    assert_eq!(
        refusals("[pkw_pzd]\nmodule = \"MOD_PKW_PZD_16\"\nsubslot = 2\n"),
        [(
            3,
            11,
            "\"MOD_PKW_PZD_16\" has no submodule in subslot 2 (its subslots: 1)".to_owned()
        )]
    );
}

#[test]
fn a_name_two_items_share_needs_the_id() {
    let shared = edited(
        "<Name TextId=\"T_MOD_NAME\"/>",
        "<Name TextId=\"T_DAP_NAME\"/>",
    );
    assert_eq!(
        refusals_on(
            &shared,
            "[pkw_pzd]\nmodule = \"Goodrive350 PROFINET card\"\n"
        ),
        [(
            2,
            10,
            "\"Goodrive350 PROFINET card\" is the name of 2 items: give the ID".to_owned()
        )]
    );
    let mut device = device(&shared);
    assert_eq!(
        overlay::apply("[pkw_pzd]\nmodule = \"MOD_PKW_PZD_16\"\n", &mut device),
        vec![]
    );
    assert_eq!(marked(&device), [("MOD_PKW_PZD_16".to_owned(), 1)]);
}

#[test]
fn a_module_without_submodules() {
    let text = card();
    let (start, end) = (
        text.find(
            "          <VirtualSubmoduleList>\n            <VirtualSubmoduleItem ID=\"SUB_DAP\"",
        )
        .expect("the access point's submodules"),
        text.find("          <SystemDefinedSubmoduleList>")
            .expect("its system submodules"),
    );
    let bare = format!("{}{}", &text[..start], &text[end..]);
    assert_eq!(
        refusals_on(&bare, "[pkw_pzd]\nmodule = \"DAP_GD350_PN\"\nsubslot = 1\n"),
        [(2, 10, "\"DAP_GD350_PN\" has no submodule".to_owned())]
    );
}

#[test]
fn images_that_are_not_16_words_each_way() {
    // The access point's own submodule has no IO data.
    assert_eq!(
        refusals("[pkw_pzd]\nmodule = \"DAP_GD350_PN\"\n"),
        [(
            2,
            10,
            "submodule `SUB_DAP` in subslot 1 has 0 input bytes and 0 output bytes; a PKW/PZD \
             image is 32 each way (16 words)"
                .to_owned()
        )]
    );
    let short = edited("<DataItem DataType=\"Unsigned16\" TextId=\"T_IN_16\"/>", "");
    assert_eq!(
        refusals_on(
            &short,
            "[pkw_pzd]\nmodule = \"MOD_PKW_PZD_16\"\nsubslot = 1\n"
        ),
        [(
            3,
            11,
            "submodule `SUB_PKW_PZD_16` in subslot 1 has 30 input bytes and 32 output bytes; a \
             PKW/PZD image is 32 each way (16 words)"
                .to_owned()
        )]
    );
    let unknown = edited(
        "<DataItem DataType=\"Unsigned16\" TextId=\"T_OUT_16\"/>",
        "<DataItem DataType=\"Unsigned17\" TextId=\"T_OUT_16\"/>",
    );
    assert_eq!(
        refusals_on(&unknown, "[pkw_pzd]\nmodule = \"MOD_PKW_PZD_16\"\n"),
        [(
            2,
            10,
            "submodule `SUB_PKW_PZD_16` in subslot 1 has 32 input bytes and an unknown number of \
             output bytes; a PKW/PZD image is 32 each way (16 words)"
                .to_owned()
        )]
    );
}

#[test]
fn several_submodules_need_a_subslot() {
    let two = edited(
        "            </VirtualSubmoduleItem>\n          </VirtualSubmoduleList>\n        </ModuleItem>",
        "            </VirtualSubmoduleItem>\n            <VirtualSubmoduleItem ID=\"SUB_2\" \
         SubmoduleIdentNumber=\"0x11\"><IOData><Input><DataItem DataType=\"Unsigned32\" \
         TextId=\"T_IN_1\"/></Input></IOData></VirtualSubmoduleItem>\n          \
         </VirtualSubmoduleList>\n        </ModuleItem>",
    );
    assert_eq!(
        refusals_on(&two, "[pkw_pzd]\nmodule = \"MOD_PKW_PZD_16\"\n"),
        [(
            2,
            10,
            "\"MOD_PKW_PZD_16\" has 2 submodules (subslots 1, 2): say which with `subslot = N`"
                .to_owned()
        )]
    );
    let mut device = device(&two);
    assert_eq!(
        overlay::apply(
            "[pkw_pzd]\nmodule = \"MOD_PKW_PZD_16\"\nsubslot = 1\n",
            &mut device
        ),
        vec![]
    );
    assert_eq!(marked(&device), [("MOD_PKW_PZD_16".to_owned(), 1)]);
}

#[test]
fn keys_and_values_of_the_wrong_kind() {
    assert_eq!(
        refusals("[pkw_pzd]\noutput = 150\nmodule = 5\nsubslot = \"1\"\n"),
        [
            (
                2,
                1,
                "`output` is not a key of [pkw_pzd] for a GSDML file (module = \"ID or name\", \
                 subslot = N)"
                    .to_owned()
            ),
            (
                3,
                10,
                "`module` is the ID or name of a ModuleItem or DeviceAccessPointItem: module = \
                 \"MOD_1\""
                    .to_owned()
            ),
            (
                4,
                11,
                "`subslot` is a subslot number: subslot = 1".to_owned()
            ),
        ]
    );
    assert_eq!(
        refusals("[pkw_pzd]\nmodule = \"MOD_PKW_PZD_16\"\nsubslot = 70000\n"),
        [(
            3,
            11,
            "`subslot` is a subslot number (0..=65535), not 70000".to_owned()
        )]
    );
    assert_eq!(
        refusals("\n[pkw_pzd]\nsubslot = 1\n"),
        [(
            2,
            2,
            "[pkw_pzd] needs `module = \"ID or name\"` (and `subslot = N` when the module has \
             several submodules)"
                .to_owned()
        )]
    );
}

/// As `edsgen generate` and the builder show it: the overlay's file, line and column.
#[test]
fn a_refusal_renders_with_the_overlay_s_file_and_line() {
    let toml = "[pkw_pzd]\nmodule = \"MOD_PKW_PZD_16\"\nsubslot = 3\n";
    let mut device = device(&card());
    let diags = overlay::apply(toml, &mut device);
    let shown = render::human("eds/goodrive350-pn.toml", toml, &diags, false);
    assert_eq!(
        shown,
        "error[EDS708]: \"MOD_PKW_PZD_16\" has no submodule in subslot 3 (its subslots: 1)\n\
         \x20--> eds/goodrive350-pn.toml:3:11\n\
         \x20 |\n\
         3 | subslot = 3\n\
         \x20 |           ^ [pkw_pzd] ignored\n\
         \x20 |\n\n"
    );
}
