//! Shared by the simulator tests: a small device whose description exercises what the bundled
//! cards do not (a writable string, a DOMAIN, limits, a DCF's values), read from text.
// Each test crate uses only some of these helpers.
#![allow(dead_code)]

use std::path::Path;

use edsgen_model::model::Device;

/// A device with the CiA 301 communication objects, one RPDO and one TPDO, and application
/// objects 2000h (VISIBLE_STRING rw), 2001h (DOMAIN rw), 2002h (UNSIGNED16 rww, 10 to 1000),
/// 2003h (INTEGER16 rwr), 2004h (REAL32 rw, -1.5 to 2.5) and 2005h (BOOLEAN rw).
pub const DEVICE_EDS: &str = "\
[FileInfo]
FileName=sim.eds
EDSVersion=4.0
Description=simulator test device

[DeviceInfo]
VendorName=edsgen
VendorNumber=0x1234
ProductName=sim
ProductNumber=0x5
RevisionNumber=0x6
NrOfRXPDO=1
NrOfTXPDO=1

[MandatoryObjects]
SupportedObjects=3
1=0x1000
2=0x1001
3=0x1018

[OptionalObjects]
SupportedObjects=8
1=0x1005
2=0x1017
3=0x1200
4=0x1400
5=0x1600
6=0x1800
7=0x1A00
8=0x1014

[ManufacturerObjects]
SupportedObjects=6
1=0x2000
2=0x2001
3=0x2002
4=0x2003
5=0x2004
6=0x2005

[1000]
ParameterName=Device type
ObjectType=0x7
DataType=0x0007
AccessType=ro
DefaultValue=0x00020192
PDOMapping=0

[1001]
ParameterName=Error register
ObjectType=0x7
DataType=0x0005
AccessType=ro
DefaultValue=0
PDOMapping=0

[1005]
ParameterName=COB-ID SYNC
ObjectType=0x7
DataType=0x0007
AccessType=rw
DefaultValue=0x80
PDOMapping=0

[1014]
ParameterName=COB-ID EMCY
ObjectType=0x7
DataType=0x0007
AccessType=rw
DefaultValue=$NODEID+0x80
PDOMapping=0

[1017]
ParameterName=Producer heartbeat time
ObjectType=0x7
DataType=0x0006
AccessType=rw
DefaultValue=0
PDOMapping=0

[1018]
ParameterName=Identity object
ObjectType=0x9
SubNumber=3

[1018sub0]
ParameterName=Number of entries
ObjectType=0x7
DataType=0x0005
AccessType=ro
DefaultValue=2

[1018sub1]
ParameterName=Vendor-ID
ObjectType=0x7
DataType=0x0007
AccessType=ro
DefaultValue=0x1234

[1018sub2]
ParameterName=Product code
ObjectType=0x7
DataType=0x0007
AccessType=ro
DefaultValue=0x5

[1200]
ParameterName=SDO server parameter
ObjectType=0x9
SubNumber=3

[1200sub0]
ParameterName=Highest sub-index supported
ObjectType=0x7
DataType=0x0005
AccessType=ro
DefaultValue=2

[1200sub1]
ParameterName=COB-ID client to server
ObjectType=0x7
DataType=0x0007
AccessType=ro
DefaultValue=$NODEID+0x600

[1200sub2]
ParameterName=COB-ID server to client
ObjectType=0x7
DataType=0x0007
AccessType=ro
DefaultValue=$NODEID+0x580

[1400]
ParameterName=RPDO1 communication parameter
ObjectType=0x9
SubNumber=3

[1400sub0]
ParameterName=Highest sub-index supported
ObjectType=0x7
DataType=0x0005
AccessType=ro
DefaultValue=2

[1400sub1]
ParameterName=COB-ID used by RPDO
ObjectType=0x7
DataType=0x0007
AccessType=rw
DefaultValue=$NODEID+0x200

[1400sub2]
ParameterName=Transmission type
ObjectType=0x7
DataType=0x0005
AccessType=rw
DefaultValue=255

[1600]
ParameterName=RPDO1 mapping parameter
ObjectType=0x9
SubNumber=3

[1600sub0]
ParameterName=Number of mapped objects
ObjectType=0x7
DataType=0x0005
AccessType=rw
DefaultValue=1

[1600sub1]
ParameterName=Mapped object 1
ObjectType=0x7
DataType=0x0007
AccessType=rw
DefaultValue=0x20020010

[1600sub2]
ParameterName=Mapped object 2
ObjectType=0x7
DataType=0x0007
AccessType=rw
DefaultValue=0

[1800]
ParameterName=TPDO1 communication parameter
ObjectType=0x9
SubNumber=3

[1800sub0]
ParameterName=Highest sub-index supported
ObjectType=0x7
DataType=0x0005
AccessType=ro
DefaultValue=2

[1800sub1]
ParameterName=COB-ID used by TPDO
ObjectType=0x7
DataType=0x0007
AccessType=rw
DefaultValue=$NODEID+0x180

[1800sub2]
ParameterName=Transmission type
ObjectType=0x7
DataType=0x0005
AccessType=rw
DefaultValue=1

[1A00]
ParameterName=TPDO1 mapping parameter
ObjectType=0x9
SubNumber=3

[1A00sub0]
ParameterName=Number of mapped objects
ObjectType=0x7
DataType=0x0005
AccessType=rw
DefaultValue=1

[1A00sub1]
ParameterName=Mapped object 1
ObjectType=0x7
DataType=0x0007
AccessType=rw
DefaultValue=0x20030010

[1A00sub2]
ParameterName=Mapped object 2
ObjectType=0x7
DataType=0x0007
AccessType=rw
DefaultValue=0

[2000]
ParameterName=Device label
ObjectType=0x7
DataType=0x0009
AccessType=rw
DefaultValue=sim
PDOMapping=0

[2001]
ParameterName=Program
ObjectType=0x7
DataType=0x000F
AccessType=rw
PDOMapping=0

[2002]
ParameterName=Target speed
ObjectType=0x7
DataType=0x0006
AccessType=rww
LowLimit=10
HighLimit=1000
DefaultValue=100
PDOMapping=1

[2003]
ParameterName=Actual speed
ObjectType=0x7
DataType=0x0003
AccessType=rwr
DefaultValue=-2
PDOMapping=1

[2004]
ParameterName=Gain
ObjectType=0x7
DataType=0x0008
AccessType=rw
LowLimit=-1.5
HighLimit=2.5
DefaultValue=0.5
PDOMapping=1

[2005]
ParameterName=Enabled
ObjectType=0x7
DataType=0x0001
AccessType=rw
DefaultValue=1
PDOMapping=1
";

/// Reads description text as if from a file named `name` (the extension picks the reader).
pub fn device(name: &str, text: &str) -> Device {
    edsgen_model::read::read_bytes(Path::new(name), text.as_bytes()).device
}

/// The test device of [`DEVICE_EDS`].
pub fn test_device() -> Device {
    device("sim.eds", DEVICE_EDS)
}

/// The test device as a DCF: node-ID 0x0A commissioned, 2002h configured to 500 and 1017h to
/// 1000 ms.
pub fn test_dcf() -> Device {
    let text = DEVICE_EDS
        .replace(
            "DefaultValue=100\nPDOMapping=1",
            "DefaultValue=100\nParameterValue=500\nPDOMapping=1",
        )
        .replace(
            "[1017]\nParameterName=Producer heartbeat time\nObjectType=0x7\nDataType=0x0006\nAccessType=rw\nDefaultValue=0",
            "[1017]\nParameterName=Producer heartbeat time\nObjectType=0x7\nDataType=0x0006\nAccessType=rw\nDefaultValue=0\nParameterValue=1000",
        )
        + "\n[DeviceComissioning]\nNodeID=0x0A\nBaudrate=250\n";
    device("sim.dcf", &text)
}
