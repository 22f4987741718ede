use super::*;
use std::path::Path;

/// A modular slave of three slots: slot 1 takes only the PPO modules, slots 2-3 anything.
const GSD: &str = include_str!("modular.gsd");

fn dp() -> Dp {
    crate::read::read_bytes(Path::new("modular.gsd"), GSD.as_bytes())
        .device
        .dp()
        .cloned()
        .expect("a GSD")
}

fn choices(texts: &[&str]) -> Vec<ModuleChoice> {
    parse_choices(texts).expect("choices")
}

#[test]
fn choices_parse_with_and_without_a_slot() {
    assert_eq!(
        parse_choice("4 PKW, 2 PZD (PPO 1)"),
        Ok(ModuleChoice {
            slot: None,
            module: "4 PKW, 2 PZD (PPO 1)".into()
        })
    );
    assert_eq!(
        parse_choice(" 2 = 8 DI "),
        Ok(ModuleChoice {
            slot: Some(2),
            module: "8 DI".into()
        })
    );
    // Not a number before `=`: the whole text is the name.
    assert_eq!(parse_choice("a=b").map(|c| c.slot), Ok(None));
    assert_eq!(
        parse_choice("3="),
        Err("`3=`: no module named (write SLOT=NAME or NAME)".into())
    );
    assert_eq!(
        parse_choice("99999999999=x"),
        Err("`99999999999=x`: slot `99999999999` is too large".into())
    );
}

#[test]
fn a_chosen_configuration_is_its_modules_in_slot_order() {
    let dp = dp();
    let config = choose_dp(
        &dp,
        &choices(&["4 pkw,  2 PZD (ppo 1)", "3=16 words out", "2=8 DI"]),
    )
    .expect("allowed");
    assert_eq!(
        config.slots,
        [
            DpPlugged { slot: 1, module: 0 },
            DpPlugged { slot: 2, module: 2 },
            DpPlugged { slot: 3, module: 3 }
        ]
    );
    assert_eq!(config.config_bytes(&dp), [0xF3, 0xF1, 0x10, 0x6F]);
    // Inputs 8 + 4 + 1, outputs 8 + 4 + 32.
    assert_eq!(config.io_lengths(&dp), (13, 44));
}

#[test]
fn a_gap_takes_the_slot_default_and_the_default_is_the_first_module() {
    let dp = dp();
    let config = choose_dp(&dp, &choices(&["1=0 PKW, 2 PZD (PPO 3)", "3=8 DI"])).unwrap();
    assert_eq!(config.config_bytes(&dp), [0xF1, 0x10, 0x10]);
    assert_eq!(dp.configuration().config_bytes(&dp), [0xF3, 0xF1]);
}

#[test]
fn what_the_slave_would_refuse_is_said() {
    let dp = dp();
    let errors = |texts: &[&str]| choose_dp(&dp, &choices(texts)).unwrap_err();
    assert_eq!(
        errors(&["8 DI", "PPO 9", "2=0 PKW, 2 PZD (PPO 3)", "2=8 DI"]),
        [
            "slot 2: no module \"PPO 9\"; did you mean:\n  \"8 DI\"\n  \"16 words out\"\n  \"4 PKW, 2 PZD (PPO 1)\"",
            "slot 2 is chosen twice",
            "slot 1 (\"Drive\") does not take module \"8 DI\"",
            "slot 2 (\"IO\") does not take module \"0 PKW, 2 PZD (PPO 3)\"",
        ]
    );
    assert_eq!(
        errors(&["5=8 DI"]),
        [
            "slot 4 is empty: a DP configuration has no gaps; choose its module",
            "4 modules: Max_Module is 3"
        ]
    );
    assert_eq!(
        errors(&["4 PKW, 2 PZD (PPO 1)", "16 words out", "16 words out"]),
        [
            "76 output bytes: Max_Output_Len is 48",
            "88 bytes of inputs and outputs: Max_Data_Len is 70"
        ]
    );
    assert_eq!(errors(&[]), ["no module chosen"]);
}

#[test]
fn chk_cfg_bytes_are_recognised_as_an_allowed_combination() {
    let dp = dp();
    let found = match_dp_cfg(&dp, &[0xF1, 0x10, 0x6F]).expect("PPO 3, 8 DI, 16 words out");
    assert_eq!(
        found.slots.iter().map(|p| p.module).collect::<Vec<_>>(),
        [1, 2, 3]
    );
    // F3 F1 is PPO 1, not PPO 3 after something: the search backtracks to the allowed reading.
    assert_eq!(
        match_dp_cfg(&dp, &[0xF3, 0xF1]).map(|c| c.slots.len()),
        Some(1)
    );
    // 8 DI is not allowed in slot 1; four modules are too many; unknown bytes.
    assert_eq!(match_dp_cfg(&dp, &[0x10]), None);
    assert_eq!(match_dp_cfg(&dp, &[0xF1, 0x10, 0x10, 0x10]), None);
    assert_eq!(match_dp_cfg(&dp, &[0xF1, 0x77]), None);
    assert_eq!(match_dp_cfg(&dp, &[]), None);
}

/// A modular slave with module parameters, as DPV10008.gsd (the gsd-corpus) writes them: its
/// own 3 bytes, AI16's 4 (two Unsigned16 limits), DO8's 1 (two bits over a constant).
const PRM_GSD: &str = include_str!("module_prm.gsd");

#[test]
fn set_prm_carries_each_modules_parameters_after_the_slaves_in_slot_order() {
    let dp = crate::read::read_bytes(Path::new("prm.gsd"), PRM_GSD.as_bytes())
        .device
        .dp()
        .cloned()
        .expect("a GSD");
    let plugged = choose_dp(&dp, &choices(&["DO8", "DI8", "AI16"])).expect("allowed");
    // DO8: 0x05 with bit 0 cleared (hot = 0) and bit 1 set (cool = 1); DI8 none; AI16 the
    // limits big-endian.
    assert_eq!(plugged.module_prm_data(&dp), [0x06, 0x1F, 0x40, 0xF0, 0x60]);
    assert_eq!(
        plugged.user_prm_data(&dp),
        [0, 0, 0, 0x06, 0x1F, 0x40, 0xF0, 0x60]
    );
    let without = choose_dp(&dp, &choices(&["DI8"])).expect("allowed");
    assert_eq!(without.user_prm_data(&dp), [0, 0, 0]);
}
