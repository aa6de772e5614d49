within Bicycle;
package Bicycles "Bicycles assembled from components, exported as FMUs"
  extends Bicycle.Icons.Package;
end Bicycles;
