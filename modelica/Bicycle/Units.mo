within Bicycle;
package Units "SI unit types used by the library (same definitions as Modelica.Units.SI)"
  extends Bicycle.Icons.Package;
  type Time = Real(final quantity = "Time", final unit = "s");
  type Angle = Real(final quantity = "Angle", final unit = "rad", displayUnit = "deg");
  type AngularVelocity = Real(final quantity = "AngularVelocity", final unit = "rad/s");
  type AngularMomentum = Real(final quantity = "AngularMomentum", final unit = "kg.m2/s");
  type AngularAcceleration = Real(final quantity = "AngularAcceleration", final unit = "rad/s2");
  type Torque = Real(final quantity = "Torque", final unit = "N.m");
  type Energy = Real(final quantity = "Energy", final unit = "J");
  type Mass = Real(final quantity = "Mass", final unit = "kg", min = 0);
  type Length = Real(final quantity = "Length", final unit = "m");
  type Position = Real(final quantity = "Length", final unit = "m");
  type Distance = Real(final quantity = "Length", final unit = "m", min = 0);
  type Velocity = Real(final quantity = "Velocity", final unit = "m/s");
  type Acceleration = Real(final quantity = "Acceleration", final unit = "m/s2");
  type MomentOfInertia = Real(final quantity = "MomentOfInertia", final unit = "kg.m2");
  type AngularMomentumIntegral = Real(final quantity = "AngularMomentumIntegral", final unit = "kg.m2") "Time integral of an angular momentum (kg.m2/s times s), e.g. J_r*theta";
  type FirstMomentOfMass = Real(final quantity = "FirstMomentOfMass", final unit = "kg.m") "Mass times length (static moment, gyrostatic coefficient, coefficient of an equation of motion)";
  type MassCoefficient = Real(final quantity = "Mass", final unit = "kg") "Signed coefficient with the dimension of a mass (no lower bound, unlike Mass)";
  type DimensionlessRatio = Real(final quantity = "DimensionlessRatio", final unit = "1") "Dimensionless ratio";
  annotation(Documentation(info = "<html>
<p>The Modelica Standard Library is not a dependency of this package (the FMU compiler flattens
the package on its own), so the few SI types needed are declared here exactly as in
<code>Modelica.Units.SI</code>. <code>AngularMomentumIntegral</code> has no counterpart there: it is
the quantity <code>J_r*theta</code> through which a leaning upper body enters the momentum-form
frame model (see <code>Components.RearFrameWithLean</code>).</p>
</html>"));
end Units;
