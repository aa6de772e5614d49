within Bicycle.Bicycles;
partial model PartialWhippleParameters "The 26 parameters of the Whipple bicycle (Meijaard et al. 2007, Table 1)"
  parameter Bicycle.Units.Length w(min = 1e-6) "Wheelbase w";
  parameter Bicycle.Units.Length c "Trail c (positive: front contact point behind the steer axis)";
  parameter Bicycle.Units.Angle lam(min = -1.5707963267948966, max = 1.5707963267948966) "Steer-axis tilt lam from the vertical (pi/2 - head angle)";
  parameter Bicycle.Units.Acceleration g(min = 0) "Gravitational acceleration g";
  parameter Bicycle.Units.Length rR(min = 1e-6) "Rear wheel radius rR (centre height of the upright wheel)";
  parameter Bicycle.Units.Mass mR(min = 0) "Rear wheel mass mR";
  parameter Bicycle.Units.MomentOfInertia IRxx(min = 0) "Rear wheel diametral inertia IRxx = IRzz";
  parameter Bicycle.Units.MomentOfInertia IRyy(min = 0) "Rear wheel spin inertia IRyy";
  parameter Bicycle.Units.Position xB "Rear frame centre of mass: x coordinate xB (forward)";
  parameter Bicycle.Units.Position zB(max = 0) "Rear frame centre of mass: z coordinate zB (down; negative above the ground)";
  parameter Bicycle.Units.Mass mB(min = 0) "Rear frame mass mB";
  parameter Bicycle.Units.MomentOfInertia IBxx(min = 0) "Rear frame inertia-tensor element IBxx about its centre of mass";
  parameter Bicycle.Units.MomentOfInertia IBxz "Rear frame inertia-tensor element IBxz about its centre of mass";
  parameter Bicycle.Units.MomentOfInertia IByy(min = 0) "Rear frame inertia-tensor element IByy about its centre of mass";
  parameter Bicycle.Units.MomentOfInertia IBzz(min = 0) "Rear frame inertia-tensor element IBzz about its centre of mass";
  parameter Bicycle.Units.Position xH "Front frame centre of mass: x coordinate xH (forward)";
  parameter Bicycle.Units.Position zH(max = 0) "Front frame centre of mass: z coordinate zH (down; negative above the ground)";
  parameter Bicycle.Units.Mass mH(min = 0) "Front frame mass mH";
  parameter Bicycle.Units.MomentOfInertia IHxx(min = 0) "Front frame inertia-tensor element IHxx about its centre of mass";
  parameter Bicycle.Units.MomentOfInertia IHxz "Front frame inertia-tensor element IHxz about its centre of mass";
  parameter Bicycle.Units.MomentOfInertia IHyy(min = 0) "Front frame inertia-tensor element IHyy about its centre of mass";
  parameter Bicycle.Units.MomentOfInertia IHzz(min = 0) "Front frame inertia-tensor element IHzz about its centre of mass";
  parameter Bicycle.Units.Length rF(min = 1e-6) "Front wheel radius rF (centre height of the upright wheel)";
  parameter Bicycle.Units.Mass mF(min = 0) "Front wheel mass mF";
  parameter Bicycle.Units.MomentOfInertia IFxx(min = 0) "Front wheel diametral inertia IFxx = IFzz";
  parameter Bicycle.Units.MomentOfInertia IFyy(min = 0) "Front wheel spin inertia IFyy";
  annotation(
    Documentation(info = "<html>
<p>The parameters of the Whipple bicycle that <a href=\"modelica://Bicycle.Bicycles.Whipple\">Whipple</a>,
<a href=\"modelica://Bicycle.Bicycles.WhippleRider\">WhippleRider</a> and
<a href=\"modelica://Bicycle.Bicycles.WhippleLinear\">WhippleLinear</a> extend: the symbols of Meijaard et al.
(2007), Table 1, in their conventions (x forward, y right, z down, origin at the rear contact point; inertias
about each body's own centre of mass, wheels axisymmetric). Each model binds them to the constants of its
replaceable package <code>Data</code> in its <code>extends</code> clause, e.g.
<code>extends PartialWhippleParameters(w = Data.w, ...)</code>, <code>Data</code> being a data set of
<a href=\"modelica://Bicycle.Records\">Records</a> constrained by
<a href=\"modelica://Bicycle.Records.PartialWhipple\">Records.PartialWhipple</a>, which declares the
same symbols.</p>
</html>"));
end PartialWhippleParameters;
