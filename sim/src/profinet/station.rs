//! What a simulated device says about itself, from its GSDML: VendorID, DeviceID, the
//! access point's `DNS_CompatibleName` (of the chosen configuration's, else the first's) (the name of station it starts with), a type of station
//! (the vendor and product family), and its instance. A `DNS_CompatibleName` with capitals is
//! lowercased: a name of station is lowercase (the PROFINET name rules), and DCP compares names
//! byte for byte, so a controller looking for the GSDML's name in any case finds it lowercase.

use edsgen_model::model::Profinet;

use super::dcp::Station;
use super::wire::Mac;

/// The station of the GSDML's access point ([`Profinet::configuration`]'s) on an interface
/// with `mac`.
pub fn from_gsdml(pn: &Profinet, mac: Mac) -> Station {
    let configuration = pn.configuration();
    let dap = configuration.access_point(pn);
    let family = pn
        .family
        .as_ref()
        .map(|(_, product)| product.clone())
        .filter(|p| !p.is_empty());
    let type_of_station = match (&pn.vendor_name, family) {
        (Some(v), Some(f)) => format!("{v} {f}"),
        (Some(v), None) => v.clone(),
        (None, Some(f)) => f,
        (None, None) => "PROFINET device".to_owned(),
    };
    Station {
        mac,
        name_of_station: dap
            .and_then(|d| d.dns_compatible_name.as_deref())
            .map(str::to_ascii_lowercase)
            .unwrap_or_default(),
        ip: [[0; 4]; 3],
        vendor_id: pn.vendor_id.as_ref().map_or(0, |v| v.value),
        device_id: pn.device_id.as_ref().map_or(0, |v| v.value),
        type_of_station,
        instance: (0, 1),
    }
}

#[cfg(test)]
mod tests {
    use edsgen_model::model::{AccessPoint, Profinet};

    use super::from_gsdml;

    #[test]
    fn a_dns_compatible_name_with_capitals_is_lowercased() {
        let pn = Profinet {
            access_points: vec![AccessPoint {
                dns_compatible_name: Some("Drive-GD350.Line-1".to_owned()),
                ..AccessPoint::default()
            }],
            ..Profinet::default()
        };
        let station = from_gsdml(&pn, [2, 0, 0, 0, 0, 1]);
        assert_eq!(station.name_of_station, "drive-gd350.line-1");
        assert_eq!(station.type_of_station, "PROFINET device");
    }
}
