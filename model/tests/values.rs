//! Each stored entry's value from a small EDS: types, initial values (constant, `$NODEID`-relative,
//! strings), limits, and an object left out whole with its diagnostic.

use std::path::Path;

use edsgen_model::model::layout::{Number, Prim, RustType};
use edsgen_model::model::{AccessType, BasicType};
use edsgen_model::read::read_bytes;
use edsgen_model::values::{
    entry_value, entry_value_without_infos, stored_values, EntryValue, Initial,
};

const EDS: &str = "\
[FileInfo]
FileName=values.eds
[DeviceInfo]
VendorName=Acme
ProductName=Values
[MandatoryObjects]
SupportedObjects=1
1=0x1000
[OptionalObjects]
SupportedObjects=0
[ManufacturerObjects]
SupportedObjects=4
1=0x2000
2=0x2001
3=0x2002
4=0x2003
[1000]
ParameterName=Device type
ObjectType=0x7
DataType=0x0007
AccessType=ro
DefaultValue=0x00020192
PDOMapping=0
[2000]
ParameterName=Speed
ObjectType=0x7
DataType=0x0003
AccessType=rw
DefaultValue=-5
LowLimit=-100
PDOMapping=1
[2001]
ParameterName=COB-ID
ObjectType=0x7
DataType=0x0007
AccessType=rw
DefaultValue=$NODEID+0x180
PDOMapping=0
[2002]
ParameterName=Too big
ObjectType=0x7
DataType=0x0005
AccessType=rw
DefaultValue=300
PDOMapping=0
[2003]
ParameterName=Name
ObjectType=0x7
DataType=0x0009
AccessType=ro
DefaultValue=ab
PDOMapping=0
";

fn device() -> edsgen_model::model::Device {
    read_bytes(Path::new("values.eds"), EDS.as_bytes()).device
}

#[test]
fn stored_values_of_a_small_eds() {
    let values = stored_values(&device());
    let at = |index: u16| values.iter().find(|v| v.index == index);
    assert_eq!(
        at(0x1000),
        Some(&EntryValue {
            index: 0x1000,
            sub: 0,
            basic: BasicType::Unsigned32,
            ty: RustType::Scalar(Prim::Unsigned(32), 4),
            access: AccessType::Ro,
            pdo_mappable: false,
            init: Initial::Raw(0x0002_0192),
            limits: None,
        })
    );
    // The missing HighLimit is the type's maximum; -5 is stored in two's complement.
    let speed = at(0x2000).expect("2000h is stored");
    assert_eq!(speed.ty, RustType::Scalar(Prim::Signed(16), 2));
    assert_eq!(speed.init, Initial::Raw((-5i64) as u64));
    assert_eq!(
        speed.limits,
        Some((Number::Integer(-100), Number::Integer(32767)))
    );
    assert!(speed.pdo_mappable);
    assert_eq!(
        at(0x2001).map(|v| &v.init),
        Some(&Initial::NodeRelative(0x180))
    );
    // A read-only string holds its default's bytes, with that capacity.
    let name = at(0x2003).expect("2003h is stored");
    assert_eq!(name.ty, RustType::Bytes(2));
    assert_eq!(name.init, Initial::Bytes(b"ab".to_vec()));
    // 300 is no UNSIGNED8 (the reader leaves it unread): the object is left out.
    assert_eq!(at(0x2002), None);
    let indices: Vec<u16> = values.iter().map(|v| v.index).collect();
    assert_eq!(indices, [0x1000, 0x2000, 0x2001, 0x2003]);
}

#[test]
fn without_infos_a_missing_default_says_nothing_and_errors_stay() {
    let mut device = device();
    let speed = device.objects.get_mut(&0x2000).expect("2000h");
    speed.subs.get_mut(&0).expect("sub 0").default = None;
    let object = &device.objects[&0x2000];
    let mut infos = Vec::new();
    let with = entry_value(&device, object, &object.subs[&0], &mut infos);
    let codes: Vec<&str> = infos.iter().map(|d| d.code()).collect();
    assert_eq!(codes, ["EDS705"]);
    let mut none = Vec::new();
    let without = entry_value_without_infos(&device, object, &object.subs[&0], &mut none);
    assert!(none.is_empty());
    assert_eq!(without, with);
    assert_eq!(without.map(|v| v.init), Some(Initial::Raw(0)));
    // An error is made all the same.
    let object = &device.objects[&0x2002];
    let mut errors = Vec::new();
    let value = entry_value_without_infos(&device, object, &object.subs[&0], &mut errors);
    assert_eq!(value, None);
    let codes: Vec<&str> = errors.iter().map(|d| d.code()).collect();
    assert_eq!(codes, ["EDS703"]);
}

#[test]
fn an_unrepresentable_default_is_a_diagnostic() {
    let device = device();
    let object = &device.objects[&0x2002];
    let mut diagnostics = Vec::new();
    let value = entry_value(&device, object, &object.subs[&0], &mut diagnostics);
    assert_eq!(value, None);
    let found: Vec<(&str, &str)> = diagnostics
        .iter()
        .map(|d| (d.code(), d.message.as_str()))
        .collect();
    assert_eq!(
        found,
        [(
            "EDS703",
            "2002h sub 0 `Too big`: the default `300` could not be read"
        ),]
    );
}
