within Bicycle.Mechanics;
package Joints "Joints between frames"
  annotation(Documentation(info = "<html><p>Revolute joints whose angle is one of the generalized
coordinates (selected by the constant vector <code>sel</code>).</p></html>"));
end Joints;
