// Numeric constants shared by Loom's shaders.

const float kPi = 3.14159265358979324;
const float kHalfPi = 1.57079632679489662;
const float kQuarterPi = 0.78539816339744831;
